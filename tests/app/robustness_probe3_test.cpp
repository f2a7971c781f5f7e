// Bad input on the surfaces of the third robustness round (issue 47: ROS
// bags, MCAP, the message decoder, stored results, reports, layouts, wheel
// CSVs, campaigns). Each test names the findings of
// shared/robustness/probe3/README.md it holds; the inputs in
// tests/data/robustness/probe3 were written by that probe's generators
// (README.md there). Every test fails on the binary the probe ran (0637daa).
#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/common/error.h"
#include "core/log/log.h"
#include "importers/log_file.h"
#include "importers/mapping.h"
#include "importers/wheel_test_csv.h"
#include "test_support.h"
#include "tests/support/hdf5_edit.h"

namespace roverlab {
namespace {

namespace fs = std::filesystem;
using test::CommandResult;
using test::quote;
using test::set_metadata;
using test::TempDir;

const std::string kExe = ROVERLAB_EXE;
const std::string kProbe = std::string(ROVERLAB_TEST_DATA) + "/robustness/probe3/";

CommandResult run_roverlab(const std::string& args) {
  return test::run_command("timeout 120 " + quote(kExe) + " " + args);
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

void expect_one_line(const CommandResult& r, int code, const std::string& named, const std::string& problem) {
  EXPECT_EQ(r.exit_code, code) << r.err << r.out;
  EXPECT_TRUE(contains(r.err, named)) << r.err;
  EXPECT_TRUE(contains(r.err, problem)) << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
}

// The InputError's text of reading `file` ("" when it reads).
std::string load_error(const std::string& file, const io::LoadOptions& options = {}) {
  try {
    (void)io::load_log(file, options);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// F1: values follow their own message's time when messages come out of time
// order (MCAP log times going back; bag header.stamps going back).
TEST(Probe3, MessagesOutOfTimeOrderKeepTheirValues) {
  const log::Log mcap = io::load_log(kProbe + "time_back.mcap").log;
  const log::Stream& j = mcap.stream("j");
  ASSERT_EQ(j.size(), 100U);
  // Message i carries a = i and was logged at 99 - i: time order is the reverse of file order.
  for (std::size_t k = 0; k < j.size(); ++k) EXPECT_EQ(j.channel("a").values[k], 99.0 - static_cast<double>(k));
  io::LoadOptions header;
  header.header_time = true;
  const log::Log bag = io::load_log(kProbe + "hdr_back.bag", header).log;
  const log::Stream& w = bag.stream("w");
  for (std::size_t k = 0; k < w.size(); ++k) {
    // With --ros-time header each row's time is its own stamp.
    EXPECT_NEAR(w.channel("header.stamp").values[k] - w.channel("header.stamp").values[0], w.time()[k], 1e-6) << k;
  }
  EXPECT_NEAR(w.channel("header.stamp").values[0], 1700000000.01, 1e-6);
}

// F4: a JSON key that collides with a "~2" suffix made two values go to one
// column (reads past a column's end, values never in the file).
TEST(Probe3, SuffixedNamesAreUniqueAgainstEveryName) {
  const log::Log lg = io::load_log(kProbe + "labels_collide.mcap").log;
  const log::Stream& j = lg.stream("j");
  const auto& p = j.channel("p").values;
  ASSERT_EQ(p.size(), j.size());
  EXPECT_EQ(p[0], -1.0);
  for (std::size_t k = 1; k < p.size(); ++k) ASSERT_TRUE(std::isnan(p[k])) << "row " << k << ": " << p[k];
  for (const auto& c : j.channels()) EXPECT_EQ(c.values.size(), j.size()) << c.name;
}

// F5, F6: channels a topic may make are capped (16.7 million from a 5 kB bag;
// a new joint in every message made memory quadratic), named in the refusal.
TEST(Probe3, ChannelsPerTopicAreCappedAndNamed) {
  auto start = std::chrono::steady_clock::now();
  const std::string nested = load_error(kProbe + "channels_64pow4.bag");
  EXPECT_TRUE(contains(nested, "the cap on a topic's channels")) << nested;
  EXPECT_TRUE(contains(nested, "topic /wide")) << nested;
  EXPECT_LT(seconds_since(start), 10.0);
  start = std::chrono::steady_clock::now();
  const std::string sparse = load_error(kProbe + "newnames_16000.bag");
  EXPECT_TRUE(contains(sparse, "most of them missing from most messages")) << sparse;
  EXPECT_LT(seconds_since(start), 10.0);
}

// F7: chunk indexes that all point at one 1 GiB chunk (a 50 kB file).
TEST(Probe3, McapChunksAreDecompressedOnceAndWithinABudget) {
  const auto start = std::chrono::steady_clock::now();
  const std::string e = load_error(kProbe + "bomb_index200.mcap");
  EXPECT_TRUE(contains(e, "two chunk indexes point into the chunk")) << e;
  EXPECT_LT(seconds_since(start), 10.0);
}

// F14: two definitions of one type name on one topic were decoded with the first.
TEST(Probe3, TwoDefinitionsOnOneTopicAreRefused) {
  const std::string e = load_error(kProbe + "two_defs.bag");
  EXPECT_TRUE(contains(e, "two different definitions of probe/XY")) << e;
}

// F18: damaged bags read as empty or short.
TEST(Probe3, ABagShortOfItsIndexIsRefused) {
  const std::string op7 = load_error(kProbe + "msg_op_7.bag");
  EXPECT_TRUE(contains(op7, "the index counts 200 messages")) << op7;
  const std::string short_count = load_error(kProbe + "chunk_count_minus1.bag");
  EXPECT_TRUE(contains(short_count, "its index lists more")) << short_count;
  EXPECT_EQ(load_error(kProbe + "valid.bag"), "");
}

// F19: streams are found by name through an index, not a scan (65,535 topics were quadratic).
TEST(Probe3, StreamsAreFoundByNameInLinearTime) {
  const auto start = std::chrono::steady_clock::now();
  log::Log lg;
  constexpr int kStreams = 200'000;
  for (int k = 0; k < kStreams; ++k) lg.add_stream(log::Stream("topic/" + std::to_string(k), {0.0}));
  for (int k = 0; k < kStreams; ++k) ASSERT_NE(lg.find_stream("topic/" + std::to_string(k)), nullptr);
  EXPECT_EQ(lg.find_stream("topic/x"), nullptr);
  EXPECT_THROW(lg.add_stream(log::Stream("topic/7", {0.0})), DataError);
  EXPECT_LT(seconds_since(start), 5.0);  // a scan: 2e10 comparisons
}

// An MCAP file of `topics` JSON topics /t0, /t1, ..., one message {"v": k}
// each (or `body`), unchunked and without a summary (the MCAP spec's records,
// little-endian).
void write_many_topics_mcap(const std::string& path, int topics, const std::string& body = "") {
  std::string out("\x89MCAP0\r\n", 8);
  const auto u16 = [](std::string& b, std::uint16_t v) { b.append(reinterpret_cast<const char*>(&v), 2); };
  const auto u32 = [](std::string& b, std::uint32_t v) { b.append(reinterpret_cast<const char*>(&v), 4); };
  const auto u64 = [](std::string& b, std::uint64_t v) { b.append(reinterpret_cast<const char*>(&v), 8); };
  const auto text = [&](std::string& b, const std::string& t) {
    u32(b, static_cast<std::uint32_t>(t.size()));
    b += t;
  };
  const auto record = [&](char op, const std::string& body) {
    out += op;
    u64(out, body.size());
    out += body;
  };
  std::string header;
  text(header, "");
  text(header, "roverlab-test");
  record(0x01, header);
  for (int k = 0; k < topics; ++k) {
    std::string channel;
    u16(channel, static_cast<std::uint16_t>(k + 1));
    u16(channel, 0);  // no schema: JSON
    text(channel, "/t" + std::to_string(k));
    text(channel, "json");
    u32(channel, 0);  // no channel metadata
    record(0x04, channel);
    std::string message;
    u16(message, static_cast<std::uint16_t>(k + 1));
    u32(message, 0);
    u64(message, 1700000000000000000ULL + static_cast<std::uint64_t>(k) * 1000000ULL);
    u64(message, 1700000000000000000ULL + static_cast<std::uint64_t>(k) * 1000000ULL);
    record(0x05, message + (body.empty() ? "{\"v\": " + std::to_string(k) + "}" : body));
  }
  std::string data_end;
  u32(data_end, 0);  // no data-section CRC
  record(0x0F, data_end);
  std::string footer;
  u64(footer, 0);
  u64(footer, 0);
  u32(footer, 0);
  record(0x02, footer);
  out += std::string("\x89MCAP0\r\n", 8);
  std::ofstream(path, std::ios::binary) << out;
}

// The attributes and datasets of /metadata in `log_path`.
std::pair<int, std::vector<std::string>> metadata_layout(const std::string& log_path) {
  const hid_t f = H5Fopen(log_path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t g = H5Gopen2(f, "/metadata", H5P_DEFAULT);
  H5O_info_t info;
  H5Oget_info(g, &info);
  std::vector<std::string> links;
  H5Literate(
      g, H5_INDEX_NAME, H5_ITER_INC, nullptr,
      [](hid_t, const char* name, const H5L_info_t*, void* data) {
        static_cast<std::vector<std::string>*>(data)->emplace_back(name);
        return 0;
      },
      &links);
  H5Gclose(g);
  H5Fclose(f);
  return {static_cast<int>(info.num_attrs), links};
}

// F19: convert of 65,535 topics spent minutes in libhdf5 appending one
// metadata attribute per topic to /metadata's header; a log with many entries
// keeps them in one table, read back whole.
TEST(Probe3, ManyTopicsConvertAndReadBack) {
  TempDir dir;
  constexpr int kTopics = 5000;
  const std::string mcap = dir.file("many.mcap"), out = dir.file("many.h5");
  write_many_topics_mcap(mcap, kTopics);
  const auto start = std::chrono::steady_clock::now();
  const CommandResult r = run_roverlab("convert " + quote(mcap) + " " + quote(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_LT(seconds_since(start), 60.0);
  const auto [attributes, links] = metadata_layout(out);
  EXPECT_EQ(attributes, 0);
  EXPECT_EQ(links, std::vector<std::string>{"extra"});
  const log::Log lg = io::load_log(out).log;
  ASSERT_EQ(lg.streams().size(), static_cast<std::size_t>(kTopics));
  for (int k = 0; k < kTopics; k += 499) {
    const log::Stream& s = lg.stream("t" + std::to_string(k));
    ASSERT_EQ(s.size(), 1U);
    EXPECT_EQ(s.channel("v").values[0], k);
    EXPECT_EQ(lg.metadata.extra.at("topic /t" + std::to_string(k)), "json, 1 messages");
  }
  EXPECT_EQ(std::count_if(lg.metadata.extra.begin(), lg.metadata.extra.end(),
                          [](const auto& e) { return e.first.rfind("topic /t", 0) == 0; }),
            kTopics);
  // A few entries stay attributes, as every RoverLab log wrote them (an older
  // RoverLab reads them); a table with another shape is refused in one line.
  write_many_topics_mcap(mcap, 3);
  ASSERT_EQ(run_roverlab("convert " + quote(mcap) + " " + quote(out)).exit_code, 0);
  EXPECT_EQ(metadata_layout(out).second.size(), 0U);
  EXPECT_EQ(io::load_log(out).log.metadata.extra.at("topic /t2"), "json, 1 messages");
  const hid_t f = H5Fopen(out.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  const hsize_t n = 2;
  const hid_t space = H5Screate_simple(1, &n, nullptr);
  const hid_t set = H5Dcreate2(f, "/metadata/extra", H5T_STD_I32LE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  H5Dclose(set);
  H5Sclose(space);
  H5Fclose(f);
  expect_one_line(run_roverlab("info " + quote(out)), 3, out, "/metadata/extra: 'extra' is not a 1-D table");
}

// Fuzzing the MCAP reader (issue 47 item 3): a JSON message nested 100,000
// deep was built whole before its values past depth 64 were ignored (a
// 1 s timeout under ASan); such containers are now dropped while parsing.
// The values within reach are read as before.
TEST(Probe3, JsonNestedDeepIsReadToItsChannelsOnly) {
  TempDir dir;
  const std::string mcap = dir.file("deep.mcap");
  write_many_topics_mcap(
      mcap, 1,
      "{\"a\": 1.5, \"deep\": " + std::string(100000, '[') + std::string(100000, ']') + ", \"b\": {\"c\": 2.5}}");
  const auto start = std::chrono::steady_clock::now();
  const log::Log lg = io::load_log(mcap).log;
  EXPECT_LT(seconds_since(start), 5.0);
  const log::Stream& s = lg.stream("t0");
  ASSERT_EQ(s.channels().size(), 2U);
  EXPECT_EQ(s.channel("a").values.at(0), 1.5);
  EXPECT_EQ(s.channel("b.c").values.at(0), 2.5);
}

// Every generator's output (issue 47 item 3): a bag whose index points past
// its chunks crashed the reading process (SIGSEGV, about one run in five
// under load): the crash guard's trial only walked the messages through the
// library, the read after it decoded them too. The trial is now that read.
TEST(Probe3, ABagIndexedPastItsChunksIsRefusedEveryTime) {
  const std::string bag = kProbe + "indexdata_off_past.bag";
  for (int run = 0; run < 12; ++run) {
    const CommandResult r = run_roverlab("info " + quote(bag));
    ASSERT_EQ(r.exit_code, 3) << "run " << run << ": " << r.err;
    EXPECT_TRUE(contains(r.err, "indexdata_off_past.bag")) << r.err;
  }
}

// F17: terminal escapes in topic and joint names reach the terminal as \xHH.
TEST(Probe3, ControlCharactersInNamesAreEscaped) {
  const CommandResult r = run_roverlab("info " + quote(kProbe + "escapes.bag"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find('\x1b'), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find('\x07'), std::string::npos) << r.out;
  EXPECT_TRUE(contains(r.out, "\\x1b]0;pwned\\x07x")) << r.out;
}

// F23: a --time range outside the file wrote an empty log with exit 0.
TEST(Probe3, ATimeRangeOutsideTheFileIsRefused) {
  TempDir dir;
  const std::string out = dir.file("out.h5");
  expect_one_line(run_roverlab("convert " + quote(kProbe + "valid.bag") + " " + quote(out) + " --time 5:6"), 3,
                  "valid.bag", "no message in --time 5:6");
  EXPECT_FALSE(fs::exists(out));
}

// F15, F21: single-wheel CSVs: values beyond a physical bound, a UTF-8 BOM, a column named twice.
TEST(Probe3, WheelCsvValuesAndHeadersAreChecked) {
  const std::string huge = kProbe + "wheel_lat_all_1e308.csv";
  expect_one_line(run_roverlab("discrepancy single-wheel " + quote(huge) + " --soil dry_sand"), 3, huge,
                  "column 'lateral_force_N'");
  const io::WheelTestFile bom = io::read_wheel_test_file(kProbe + "wheel_bom_first_required.csv");
  ASSERT_FALSE(bom.points.empty());
  EXPECT_EQ(bom.points.front().wheel_label, "kapvik");
  try {
    (void)io::read_wheel_test_file(kProbe + "wheel_dup_radius_first.csv");
    ADD_FAILURE() << "radius_m twice was read";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "names column 'radius_m' twice")) << e.what();
  }
}

// F17 (wheel labels), F20: the per-wheel table escapes labels; a large study warns.
TEST(Probe3, WheelLabelsAreEscapedInTheStudysTable) {
  const CommandResult r =
      run_roverlab("discrepancy single-wheel " + quote(kProbe + "wheel_label_escape.csv") + " --soil dry_sand");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find('\x1b'), std::string::npos);
  EXPECT_TRUE(contains(r.out, "\\x1b[2J\\x1b]0;pwned\\x07kapvik")) << r.out;
}

// F22: text in a measured column of `terramechanics fit` was read as missing.
TEST(Probe3, TextInAMeasuredFitColumnIsRefused) {
  const std::string file = kProbe + "fit_lateral_text.csv";
  expect_one_line(run_roverlab("terramechanics fit " + quote(file)), 3, file,
                  "column 'lateral_force_N': cannot parse 'x'");
}

// F24, F25: an option without effect; values shown as given.
TEST(Probe3, OptionsWithoutEffectAndValuesAsGiven) {
  TempDir dir;
  const CommandResult from =
      run_roverlab("scenario flat-turn --rate 20 --slip-angle-from 10 -o " + quote(dir.file("f.h5")));
  EXPECT_EQ(from.exit_code, 2) << from.err;
  EXPECT_TRUE(contains(from.err, "--slip-angle")) << from.err;
  test::write_text(dir.file("c45.json"), R"({"format":"roverlab-campaign","version":1,"name":"x","simulations":[)"
                                         R"({"scenario":"flat-turn","seeds":[1],"slip_angle_deg":45.0000001}]})");
  const CommandResult c45 =
      run_roverlab("campaign " + quote(dir.file("c45.json")) + " -o " + quote(dir.file("runs")) + " -n");
  EXPECT_NE(c45.exit_code, 0);
  EXPECT_TRUE(contains(c45.err, "45.0000001 deg")) << c45.err;
  test::write_text(dir.file("from.json"), R"({"format":"roverlab-campaign","version":1,"name":"x","simulations":[)"
                                          R"({"scenario":"flat-turn","seeds":[1],"slip_angle_from":10}]})");
  const CommandResult alone =
      run_roverlab("campaign " + quote(dir.file("from.json")) + " -o " + quote(dir.file("runs2")) + " -n");
  EXPECT_EQ(alone.exit_code, 3) << alone.err;
  EXPECT_TRUE(contains(alone.err, "needs slip_angle_deg")) << alone.err;
  test::write_text(dir.file("m.json"), R"({"format": "roverlab-mapping", "version": 1, "name": "m",
      "streams": [{"name": "imu", "time": {"variable": "imu", "unit": "s"},
                   "channels": [{"name": "x", "variable": "imu/x", "unit": "1", "scale": 1e308}]}]})");
  try {
    (void)io::load_mapping(dir.file("m.json"));
    ADD_FAILURE() << "a scale of 1e308 was accepted";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "scale")) << e.what();
  }
}

// A simulated planar rocker-bogie log with the net-traction result stored (estimate -o).
std::string log_with_stored_result(const TempDir& dir) {
  const std::string flat = dir.file("flat.h5"), out = dir.file("estimated.h5");
  EXPECT_EQ(run_roverlab("simulate flat_60s --duration 10 -o " + quote(flat)).exit_code, 0);
  const CommandResult r = run_roverlab("estimate net-traction " + quote(flat) + " -o " + quote(out));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return out;
}

std::string read_string_dataset(hid_t file, const std::string& path) {
  const hid_t ds = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  EXPECT_GE(ds, 0) << path;
  const hid_t type = H5Dget_type(ds);
  std::string text;
  if (H5Tis_variable_str(type) > 0) {
    char* value = nullptr;
    const hid_t mem = H5Tcopy(H5T_C_S1);
    H5Tset_size(mem, H5T_VARIABLE);
    H5Dread(ds, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, &value);
    text = value != nullptr ? value : "";
    H5free_memory(value);
    H5Tclose(mem);
  } else {
    text.resize(H5Tget_size(type));
    H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, text.data());
    while (!text.empty() && text.back() == '\0') text.pop_back();
  }
  H5Tclose(type);
  H5Dclose(ds);
  return text;
}

void write_string_dataset(hid_t file, const std::string& path, const std::string& text) {
  H5Ldelete(file, path.c_str(), H5P_DEFAULT);
  const hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, text.size());
  H5Tset_cset(type, H5T_CSET_UTF8);
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t ds = H5Dcreate2(file, path.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  ASSERT_GE(ds, 0);
  ASSERT_GE(H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, text.data()), 0);
  H5Dclose(ds);
  H5Sclose(space);
  H5Tclose(type);
}

template <class Edit>
void edit_copy(const std::string& from, const std::string& to, Edit&& edit) {
  fs::copy_file(from, to, fs::copy_options::overwrite_existing);
  const hid_t f = H5Fopen(to.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  edit(f);
  H5Fclose(f);
}

// F2, F16, F13: a stored result nested 100,000 deep crashed report and gui;
// one with wrong-typed fields gave "internal error" and library text; one
// whose scenario changed in the log was reused. Each is now run again.
TEST(Probe3, StoredResultsAreBoundedShapedAndFingerprintedWithTheirMetadata) {
  TempDir dir;
  const std::string stored = log_with_stored_result(dir);
  const std::string result_path = "/results/net-traction";
  const CommandResult reused =
      run_roverlab("render " + quote(stored) + " --view traction-surface -o " + quote(dir.file("a.png")));
  ASSERT_EQ(reused.exit_code, 0) << reused.err;
  ASSERT_TRUE(contains(reused.out + reused.err, "reused the stored result")) << reused.out << reused.err;

  const std::string deep = dir.file("deep.h5");
  edit_copy(stored, deep, [&](hid_t f) {
    std::string text = read_string_dataset(f, result_path);
    ASSERT_EQ(text.back(), '}');
    text.pop_back();
    text += R"(,"deep":)" + std::string(100000 * 5, ' ') + "}";
    std::string nested;
    for (int k = 0; k < 100000; ++k) nested += R"({"x":)";
    text.replace(text.size() - 1 - 100000 * 5, 100000 * 5, nested + "1" + std::string(100000, '}'));
    write_string_dataset(f, result_path, text);
  });
  const CommandResult report = run_roverlab("report " + quote(deep) + " -o " + quote(dir.file("r_deep")));
  EXPECT_EQ(report.exit_code, 0) << report.err;
  const CommandResult gui = run_roverlab("gui " + quote(deep) + " --screenshot " + quote(dir.file("g.png")));
  EXPECT_EQ(gui.exit_code, 0) << gui.err;

  const std::string types = dir.file("types.h5");
  edit_copy(stored, types, [&](hid_t f) {
    nlohmann::json doc = nlohmann::json::parse(read_string_dataset(f, result_path));
    for (auto& [key, value] : doc.items()) {
      if (key == "configuration" || key == "input") continue;
      value = value.is_object()   ? nlohmann::json::array({1, "x", nullptr})
              : value.is_array()  ? nlohmann::json{{"x", {nullptr}}}
              : value.is_number() ? nlohmann::json("x")
                                  : nlohmann::json(3.5);
    }
    write_string_dataset(f, result_path, doc.dump());
  });
  const CommandResult typed = run_roverlab("report " + quote(types) + " -o " + quote(dir.file("r_types")));
  EXPECT_EQ(typed.exit_code, 0) << typed.err;
  EXPECT_FALSE(contains(typed.err, "json.exception")) << typed.err;

  const std::string scenario = dir.file("scenario.h5");
  edit_copy(stored, scenario, [&](hid_t f) { set_metadata(f, "scenario_json", R"({"name": "changed"})"); });
  const CommandResult changed =
      run_roverlab("render " + quote(scenario) + " --view traction-surface -o " + quote(dir.file("b.png")));
  EXPECT_FALSE(contains(changed.out + changed.err, "reused the stored result")) << changed.out << changed.err;
}

// F3: a campaign run's metrics.json nested 100,000 deep crashed `campaign report`.
TEST(Probe3, ACampaignMetricsFileNestedDeepIsRefused) {
  TempDir dir;
  const fs::path run = dir.path() / "runs" / "r1";
  fs::create_directories(run / "report");
  test::write_text((run / "run.json").string(),
                   R"({"format": "roverlab-campaign-run", "name": "r1", "kind": "scenario", "scenario": "flat-turn",)"
                   R"( "seed": 1, "effects": {}, "roverlab_version": "0.1.0"})");
  std::string deep = R"({"file":"log.h5","analyses":{"contact-angle":{"deep":)";
  for (int k = 0; k < 100000; ++k) deep += R"({"a":)";
  deep += "1" + std::string(100000, '}') + "}}}";
  test::write_text((run / "report" / "metrics.json").string(), deep);
  test::write_text((run / "report" / "index.html").string(), "<h1>RoverLab report</h1>");
  const CommandResult r = run_roverlab("campaign report " + quote(run.string()) + " -o " + quote(dir.file("out")));
  expect_one_line(r, 3, "metrics.json", "nests deeper than 64 levels");
}

// F8, F9, F25: a layout's damaged window state (dock area 77) crashed Qt;
// one channel listed 100,000 times took gigabytes; version 2^40 read as 0.
TEST(Probe3, LayoutsAreCheckedBeforeQtReadsThem) {
  TempDir dir;
  const std::string log = dir.file("ft.h5");
  ASSERT_EQ(run_roverlab("scenario flat-turn --rate 20 -o " + quote(log)).exit_code, 0);
  const std::string area77 = kProbe + "layout_state_area77.json";
  expect_one_line(
      run_roverlab("gui " + quote(log) + " --layout " + quote(area77) + " --screenshot " + quote(dir.file("a.png"))), 3,
      "layout_state_area77.json", "window state is damaged");
  nlohmann::json same = {{"format", "roverlab-layout"}, {"version", 2}};
  nlohmann::json channels = nlohmann::json::array();
  for (int k = 0; k < 100000; ++k) channels.push_back({{"stream", "imu"}, {"channel", "specific_force_x"}});
  same["plot_panes"] = {{{"name", "pane/timeseries"}, {"title", "P"}, {"channels", channels}}};
  test::write_text(dir.file("same.json"), same.dump());
  const auto start = std::chrono::steady_clock::now();
  const CommandResult once = run_roverlab("gui " + quote(log) + " --layout " + quote(dir.file("same.json")) +
                                          " --screenshot " + quote(dir.file("b.png")));
  EXPECT_EQ(once.exit_code, 0) << once.err;
  EXPECT_LT(seconds_since(start), 30.0);
  nlohmann::json many = same;
  many["plot_panes"][0]["channels"] = nlohmann::json::array();
  for (int k = 0; k < 300; ++k) {
    many["plot_panes"][0]["channels"].push_back({{"stream", "imu"}, {"channel", "c" + std::to_string(k)}});
  }
  test::write_text(dir.file("many.json"), many.dump());
  expect_one_line(run_roverlab("gui " + quote(log) + " --layout " + quote(dir.file("many.json")) + " --screenshot " +
                               quote(dir.file("c.png"))),
                  3, "many.json", "more than 256 channels");
  test::write_text(dir.file("v.json"), R"({"format": "roverlab-layout", "version": 1099511627776})");
  expect_one_line(run_roverlab("gui " + quote(log) + " --layout " + quote(dir.file("v.json")) + " --screenshot " +
                               quote(dir.file("d.png"))),
                  3, "v.json", "layout version 1099511627776");
}

// F10, F11, F12: the report's PDF of a folder named with %41 or #; the command
// to make it again quoted for a shell; a user's file that metrics.json lists kept.
TEST(Probe3, ReportPathsAndCommandsAreEncodedAndQuoted) {
  TempDir dir;
  const std::string log = dir.file("$(touch PWNED).h5");
  ASSERT_EQ(run_roverlab("scenario flat-turn --rate 20 -o " + quote(log)).exit_code, 0);
  const std::string out = dir.file("rep");
  ASSERT_EQ(run_roverlab("report " + quote(log) + " -o " + quote(out)).exit_code, 0);
  const nlohmann::json provenance = nlohmann::json::parse(test::read_text(out + "/provenance.json"));
  const std::string command = provenance.at("command").get<std::string>();
  fs::create_directories(dir.path() / "paste");
  test::write_text(dir.file("paste.sh"), "cd " + quote(dir.file("paste")) + "\nroverlab() { :; }\n" + command + "\n");
  (void)test::run_command("sh " + quote(dir.file("paste.sh")));
  EXPECT_FALSE(fs::exists(dir.path() / "paste" / "PWNED")) << command;

  test::write_text(out + "/thesis.tex", "my thesis");
  nlohmann::json metrics = nlohmann::json::parse(test::read_text(out + "/metrics.json"));
  metrics["files"].push_back("thesis.tex");
  test::write_text(out + "/metrics.json", metrics.dump());
  ASSERT_EQ(run_roverlab("report " + quote(log) + " -o " + quote(out)).exit_code, 0);
  EXPECT_TRUE(fs::exists(out + "/thesis.tex"));

  if (test::run_command("command -v chromium").exit_code != 0) GTEST_SKIP() << "no chromium for --pdf";
  fs::create_directories(dir.path() / "pdfAB");
  test::write_text(dir.file("pdfAB/index.html"), "<h1>NOT THE REPORT</h1>");
  const std::string encoded = dir.file("pdf%41B");
  const CommandResult pdf = run_roverlab("report " + quote(log) + " -o " + quote(encoded) + " --pdf");
  ASSERT_EQ(pdf.exit_code, 0) << pdf.err;
  const CommandResult text = test::run_command("pdftotext " + quote(encoded + "/report.pdf") + " -");
  if (text.exit_code == 0) {
    EXPECT_FALSE(contains(text.out, "NOT THE REPORT")) << text.out;
  }
  const CommandResult hash = run_roverlab("report " + quote(log) + " -o " + quote(dir.file("run#3")) + " --pdf");
  EXPECT_EQ(hash.exit_code, 0) << hash.err;
  EXPECT_TRUE(fs::exists(dir.file("run#3/report.pdf")));
}

}  // namespace
}  // namespace roverlab
