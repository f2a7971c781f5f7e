// Bad input on the surfaces added after the first robustness round (issue 34:
// net traction, the rover study, scenarios, smoothers, campaigns and their
// reports, the GUI's options), run as a user runs it. Each test names the
// findings of shared/robustness/new-surfaces/README.md it holds.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

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

CommandResult run_roverlab(const std::string& args) {
  // `timeout` turns a hang into a failure instead of a stuck test.
  return test::run_command("timeout 120 " + quote(kExe) + " " + args);
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

void expect_one_line(const CommandResult& r, int code, const std::string& named, const std::string& problem) {
  EXPECT_EQ(r.exit_code, code) << r.err << r.out;
  EXPECT_TRUE(contains(r.err, named)) << r.err;
  EXPECT_TRUE(contains(r.err, problem)) << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;  // one line
}

// A simulated planar rocker-bogie log (flat_60s cut to `seconds`), edited with HDF5.
class SimulatedLog {
 public:
  SimulatedLog(const TempDir& dir, const std::string& name, double seconds) : path_(dir.file(name)) {
    const CommandResult r =
        run_roverlab("simulate flat_60s --duration " + std::to_string(seconds) + " -o " + quote(path_));
    EXPECT_EQ(r.exit_code, 0) << r.err;
  }
  const std::string& path() const { return path_; }
  template <class Edit>
  void edit(Edit&& edit_file) const {
    const hid_t f = H5Fopen(path_.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    edit_file(f);
    H5Fclose(f);
  }
  std::string copy_as(const TempDir& dir, const std::string& name) const {
    const std::string to = dir.file(name);
    fs::copy_file(path_, to, fs::copy_options::overwrite_existing);
    return to;
  }

 private:
  std::string path_;
};

template <class Edit>
void edit_file(const std::string& path, Edit&& edit) {
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  ASSERT_GE(f, 0);
  edit(f);
  H5Fclose(f);
}

std::vector<double> read_doubles(hid_t file, const std::string& path) {
  const hid_t ds = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  EXPECT_GE(ds, 0) << path;
  const hid_t space = H5Dget_space(ds);
  std::vector<double> v(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
  EXPECT_GE(H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0);
  H5Sclose(space);
  H5Dclose(ds);
  return v;
}

void write_doubles(hid_t file, const std::string& path, const std::vector<double>& v) {
  const hid_t ds = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  ASSERT_GE(ds, 0) << path;
  ASSERT_GE(H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), 0);
  H5Dclose(ds);
}

// Applies `change` to every value of a dataset of an open file.
template <class Change>
void change_values(hid_t file, const std::string& path, Change&& change) {
  std::vector<double> v = read_doubles(file, path);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = change(i, v[i]);
  write_doubles(file, path, v);
}

// The names of a group's members.
std::vector<std::string> members(hid_t file, const std::string& group) {
  std::vector<std::string> names;
  const hid_t g = H5Gopen2(file, group.c_str(), H5P_DEFAULT);
  EXPECT_GE(g, 0) << group;
  hsize_t n = 0;
  H5Gget_num_objs(g, &n);
  for (hsize_t k = 0; k < n; ++k) {
    char name[256];
    H5Gget_objname_by_idx(g, k, name, sizeof name);
    names.emplace_back(name);
  }
  H5Gclose(g);
  return names;
}

// Cuts a stream of an open file to its first `samples` samples (its time and every channel).
void cut_stream(hid_t file, const std::string& stream, hsize_t samples) {
  const std::string base = "/streams/" + stream;
  std::vector<std::string> datasets = {base + "/time"};
  for (const auto& c : members(file, base + "/channels")) datasets.push_back(base + "/channels/" + c);
  for (const auto& path : datasets) {
    const hid_t ds = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
    ASSERT_GE(ds, 0) << path;
    ASSERT_GE(H5Dset_extent(ds, &samples), 0) << path;
    H5Dclose(ds);
  }
}

void delete_metadata(hid_t file, const std::string& key) {
  const hid_t g = H5Gopen2(file, "/metadata", H5P_DEFAULT);
  ASSERT_GE(g, 0);
  ASSERT_GE(H5Adelete(g, key.c_str()), 0);
  H5Gclose(g);
}

// N1, N27, N14: an empty or one-sample forces stream crashed net traction
// (SIGSEGV) and made the rover study exit 4 ("cannot create std::vector
// larger than max_size()") or print nan sigmas with exit 0.
TEST(NewSurfaces, AnEmptyOrOneSampleStreamIsNamedNotACrash) {
  TempDir dir;
  // 25 s: 1,251 samples at 50 Hz, so the streams are chunked (the log writes datasets of at most
  // 1,024 samples compact, which H5Dset_extent cannot cut).
  const SimulatedLog log(dir, "flat.h5", 25);
  const std::string empty = log.copy_as(dir, "empty.h5"), one = log.copy_as(dir, "one.h5");
  edit_file(empty, [](hid_t f) { cut_stream(f, "forces", 0); });
  edit_file(one, [](hid_t f) { cut_stream(f, "forces", 1); });
  for (const char* command : {"estimate net-traction ", "discrepancy rover "}) {
    expect_one_line(run_roverlab(command + quote(empty)), 3, empty, "stream 'forces' is empty");
    expect_one_line(run_roverlab(command + quote(one)), 3, one, "stream 'forces' has 1 sample");
  }
}

// N2, N14: a load of 1e300 N crashed the soil fit's covariance (net
// traction) and gave inf RMSE with exit 0 (rover study); a load constant at
// -50 N crashed it too.
TEST(NewSurfaces, AnAbsurdLoadIsNamedAndANegativeOneDoesNotCrash) {
  TempDir dir;
  const SimulatedLog log(dir, "flat.h5", 20);
  const std::string huge = log.copy_as(dir, "huge.h5"), negative = log.copy_as(dir, "negative.h5");
  edit_file(huge, [](hid_t f) {
    change_values(f, "/streams/forces/channels/load_1",
                  [](std::size_t i, double v) { return i >= 100 && i < 200 ? 1e300 : v; });
  });
  for (const char* command : {"estimate net-traction ", "discrepancy rover "}) {
    expect_one_line(run_roverlab(command + quote(huge)), 3, huge, "channel 'load_1': 1e+300");
  }
  edit_file(negative, [](hid_t f) {
    change_values(f, "/streams/forces/channels/load_1", [](std::size_t, double) { return -50.0; });
  });
  const CommandResult r = run_roverlab("estimate net-traction " + quote(negative));
  EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 3) << r.exit_code << r.err;
  if (r.exit_code == 3) {
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
  }
}

// N13: streams whose time bases do not overlap, a time base scaled by 1000
// and a 50 s gap were analysed with exit 0.
TEST(NewSurfaces, StreamsThatShareNoTimeBaseAreRefused) {
  TempDir dir;
  const SimulatedLog log(dir, "flat.h5", 12);
  const std::string shifted = log.copy_as(dir, "shifted.h5"), scaled = log.copy_as(dir, "scaled.h5"),
                    gap = log.copy_as(dir, "gap.h5");
  edit_file(shifted,
            [](hid_t f) { change_values(f, "/streams/forces/time", [](std::size_t, double t) { return t + 1000; }); });
  edit_file(scaled,
            [](hid_t f) { change_values(f, "/streams/imu/time", [](std::size_t, double t) { return t * 1000; }); });
  edit_file(gap, [](hid_t f) {
    for (const char* s : {"imu", "joints", "velocimeter", "forces", "commands"}) {
      change_values(f, std::string("/streams/") + s + "/time",
                    [](std::size_t i, double t) { return i >= 200 ? t + 50.0 : t; });
    }
  });
  for (const char* command : {"estimate net-traction ", "discrepancy rover "}) {
    expect_one_line(run_roverlab(command + quote(shifted)), 3, shifted, "do not share a time base");
    expect_one_line(run_roverlab(command + quote(scaled)), 3, scaled, "stream 'imu': a gap of");
    expect_one_line(run_roverlab(command + quote(gap)), 3, gap, "a gap of 50");
  }
}

// N15: constant forces, a stuck encoder or an all-zero IMU were analysed
// without a word (false soil changes, "consistent").
TEST(NewSurfaces, FlatLinedChannelsAreWarnedAbout) {
  TempDir dir;
  const SimulatedLog log(dir, "flat.h5", 12);
  const std::string fresh = run_roverlab("estimate net-traction " + quote(log.path())).out;
  EXPECT_FALSE(contains(fresh, "warning:")) << fresh;
  log.edit([](hid_t f) {
    for (const char* c : {"load_1", "load_2", "load_3"}) {
      change_values(f, std::string("/streams/forces/channels/") + c, [](std::size_t, double) { return 40.0; });
    }
  });
  const CommandResult r = run_roverlab("estimate net-traction " + quote(log.path()));
  EXPECT_TRUE(contains(r.out, "warning: stream 'forces' channel 'load_2' stays at 40 for")) << r.out << r.err;
  EXPECT_TRUE(contains(r.out, "a stuck or disconnected sensor?")) << r.out;
}

// A flying-rover log for the contact-angle estimator (200 Hz, with truth).
std::string contact_angle_log(const TempDir& dir, const std::string& name) {
  const std::string path = dir.file(name);
  const CommandResult r = run_roverlab("scenario fl-bogie-rotation --rate 200 -o " + quote(path));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return path;
}

// N3, N13: an empty truth/wheels crashed the scoring (SIGSEGV); truth
// recorded 1000 s after the estimate was scored anyway. Now the errors are
// scored only where truth exists.
TEST(NewSurfaces, ContactAnglesAreScoredOnlyWhereTruthExists) {
  TempDir dir;
  const std::string base = contact_angle_log(dir, "fl.h5");
  const std::string empty = dir.file("empty.h5"), late = dir.file("late.h5");
  fs::copy_file(base, empty);
  fs::copy_file(base, late);
  edit_file(empty, [](hid_t f) { cut_stream(f, "truth/wheels", 0); });
  edit_file(late, [](hid_t f) {
    change_values(f, "/streams/truth/wheels/time", [](std::size_t, double t) { return t + 1000; });
  });
  const CommandResult scored = run_roverlab("estimate contact-angle --json " + quote(base));
  ASSERT_EQ(scored.exit_code, 0) << scored.err;
  EXPECT_TRUE(nlohmann::json::parse(scored.out).contains("rms")) << scored.out;
  for (const std::string& file : {empty, late}) {
    for (const char* options : {"", "--no-smoother "}) {
      const CommandResult r = run_roverlab(std::string("estimate contact-angle --json ") + options + quote(file));
      ASSERT_EQ(r.exit_code, 0) << file << " " << r.err;
      EXPECT_FALSE(nlohmann::json::parse(r.out).contains("rms")) << file << r.out.substr(0, 400);
    }
  }
}

// N15: an all-zero IMU was called "consistent" without a warning.
TEST(NewSurfaces, AnAllZeroImuIsWarnedAbout) {
  TempDir dir;
  const std::string path = contact_angle_log(dir, "fl.h5");
  const CommandResult fresh = run_roverlab("estimate contact-angle " + quote(path));
  EXPECT_FALSE(contains(fresh.out, "warning:")) << fresh.out;
  edit_file(path, [](hid_t f) {
    for (const char* c : {"angular_rate_x", "angular_rate_y", "angular_rate_z", "specific_force_x", "specific_force_y",
                          "specific_force_z"}) {
      change_values(f, std::string("/streams/imu/channels/") + c, [](std::size_t, double) { return 0.0; });
    }
  });
  const CommandResult r = run_roverlab("estimate contact-angle " + quote(path));
  EXPECT_TRUE(contains(r.out, "warning: stream 'imu' channel 'angular_rate_x' stays at 0 for")) << r.out << r.err;
}

// N12: every wheel rate 0 gave "model c is the consistent candidate (mean
// NIS nan, AIC inf)", health ok and an RMS over 0 samples, exit 0.
TEST(NewSurfaces, AContactAngleRunWithoutOneMeasurementUpdateIsRefused) {
  TempDir dir;
  const std::string path = contact_angle_log(dir, "fl.h5");
  edit_file(path, [](hid_t f) {
    for (const auto& c : members(f, "/streams/wheels/channels")) {
      if (c.rfind("rate_", 0) == 0) {
        change_values(f, "/streams/wheels/channels/" + c, [](std::size_t, double) { return 0.0; });
      }
    }
  });
  for (const char* model : {"", "--model c "}) {
    expect_one_line(run_roverlab(std::string("estimate contact-angle ") + model + quote(path)), 3, path,
                    "no wheel measurement update");
  }
}

// N11: --model c said "the data reject model c" (mean NIS 0.37, 0 % above
// band) where --model auto called the same numbers consistent: the AIC, which
// only the selection computes, decided it.
TEST(NewSurfaces, OneConsistencyVerdictOnBothPaths) {
  TempDir dir;
  const std::string path = contact_angle_log(dir, "fl.h5");
  const CommandResult by_hand = run_roverlab("estimate contact-angle --json --model c " + quote(path));
  const CommandResult chosen = run_roverlab("estimate contact-angle --json " + quote(path));
  ASSERT_EQ(by_hand.exit_code, 0) << by_hand.err;
  ASSERT_EQ(chosen.exit_code, 0) << chosen.err;
  const nlohmann::json hand = nlohmann::json::parse(by_hand.out).at("model_evidence");
  const nlohmann::json selection = nlohmann::json::parse(chosen.out).at("model_selection");
  nlohmann::json c;
  for (const auto& k : selection.at("candidates")) {
    if (k.at("model") == "c") c = k;
  }
  ASSERT_FALSE(c.is_null());
  EXPECT_NEAR(hand.at("mean_nis").get<double>(), c.at("mean_nis").get<double>(), 1e-6);
  EXPECT_EQ(hand.at("consistent"), c.at("consistent")) << hand.dump() << "\n" << c.dump();
}

// A finished campaign run as `campaign report` reads it: run.json and report/metrics.json.
std::string campaign_run(const TempDir& dir, const std::string& name, const nlohmann::json& run_changes,
                         double drawbar_pull_rms) {
  const fs::path run = dir.path() / "runs" / name;
  fs::create_directories(run / "report");
  nlohmann::json doc = {{"format", "roverlab-campaign-run"},
                        {"name", name},
                        {"kind", "simulate"},
                        {"scenario", "flat_60s"},
                        {"seed", 1},
                        {"effects", nlohmann::json::object()},
                        {"roverlab_version", "test"}};
  if (run_changes.is_object()) doc.update(run_changes);
  test::write_text((run / "run.json").string(), doc.dump());
  const nlohmann::json metrics = {
      {"analyses", {{"net-traction", {{"summary", {{"drawbar_pull_rms_percent", drawbar_pull_rms}}}}}}}};
  test::write_text((run / "report" / "metrics.json").string(), metrics.dump());
  test::write_text((run / "report" / "index.html").string(), "<h1>RoverLab report</h1>");
  return run.string();
}

// N4: metrics of +-1.7e308 crashed the histogram (SIGSEGV).
TEST(NewSurfaces, ACampaignReportBinsMetricsWhoseRangeOverflows) {
  TempDir dir;
  const std::string a = campaign_run(dir, "big", {}, 1.7e308), b = campaign_run(dir, "small", {}, -1.7e308);
  const CommandResult r =
      run_roverlab("campaign report " + quote(a) + " " + quote(b) + " -o " + quote(dir.file("out")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string svg = test::read_text(dir.file("out/hist_net_traction_dp_rms_percent.svg"));
  EXPECT_TRUE(contains(svg, "(2 runs)")) << svg;
}

// N26, N19: wrong-typed run.json fields were exit 4 "internal error:
// [json.exception.type_error.302]"; a seed of 1e300 was shown as
// -9223372036854775808. N25: a run name starting with '=' became a
// spreadsheet formula in campaign.csv.
TEST(NewSurfaces, ACampaignRunsFieldsAreCheckedAndItsTextStaysText) {
  TempDir dir;
  const std::string good = campaign_run(dir, "good", {}, 1.0);
  const struct {
    const char* name;
    nlohmann::json change;
    const char* problem;
  } bad[] = {{"name_number", {{"name", 5}}, "field 'name' must be a string"},
             {"effects_text", {{"effects", {{"soil-strength", "x"}}}}, "field 'effects' must be an object of"},
             {"seed_huge", {{"seed", 1e300}}, "field 'seed' must be a whole number"},
             {"kind_list", {{"kind", {1, 2}}}, "field 'kind' must be a string"}};
  for (const auto& b : bad) {
    const std::string run = campaign_run(dir, b.name, b.change, 1.0);
    const std::string out = dir.file(std::string("out_") + b.name);
    expect_one_line(run_roverlab("campaign report " + quote(good) + " " + quote(run) + " -o " + quote(out)), 3,
                    run + "/run.json", b.problem);
    EXPECT_FALSE(fs::exists(out)) << "a failed report leaves no folder behind";
  }
  const std::string formula = campaign_run(dir, "formula", {{"name", "=HYPERLINK(\"http://x\")"}}, 1.0);
  ASSERT_EQ(run_roverlab("campaign report " + quote(formula) + " -o " + quote(dir.file("csv"))).exit_code, 0);
  const std::string csv = test::read_text(dir.file("csv/campaign.csv"));
  EXPECT_TRUE(contains(csv, "\"'=HYPERLINK(\"\"http://x\"\")\"")) << csv;
}

// N24: `campaign report -o DIR` overwrote the user's index.html, or a run's own report.
TEST(NewSurfaces, ACampaignReportNeverOverwritesWhatItDidNotWrite) {
  TempDir dir;
  const std::string run = campaign_run(dir, "good", {}, 1.0);
  const std::string mine = dir.file("mine");
  fs::create_directories(mine);
  test::write_text(mine + "/index.html", "<html>mine</html>");
  expect_one_line(run_roverlab("campaign report " + quote(run) + " -o " + quote(mine)), 2, mine,
                  "other files than a RoverLab campaign report");
  EXPECT_EQ(test::read_text(mine + "/index.html"), "<html>mine</html>");
  expect_one_line(run_roverlab("campaign report " + quote(run) + " -o " + quote(run + "/report")), 2, "report",
                  "other files than a RoverLab campaign report");
  // Over its own previous report it goes.
  const std::string out = dir.file("out");
  ASSERT_EQ(run_roverlab("campaign report " + quote(run) + " -o " + quote(out)).exit_code, 0);
  EXPECT_EQ(run_roverlab("campaign report " + quote(run) + " -o " + quote(out)).exit_code, 0);
}

// N5, N16: a 100000-pixel window crashed the GUI; --width 0 gave 559x484;
// --time nan was shown as "t = nan s". N33: --smoother-method without
// --smoother was ignored. N17: logs were written as HDF5 under .csv names.
// N34: --scenario '' was ignored.
TEST(NewSurfaces, OptionsOutOfRangeOrWithoutEffectAreUsageErrors) {
  TempDir dir;
  const std::string fl = contact_angle_log(dir, "fl.h5");
  for (const char* size : {"--width 100000", "--height 100000", "--width 0", "--height -5"}) {
    const CommandResult r = run_roverlab("gui " + quote(fl) + " --screenshot " + quote(dir.file("g.png")) + " " + size);
    EXPECT_EQ(r.exit_code, 2) << size << r.err;
    EXPECT_TRUE(contains(r.err, "16 to 8192") || contains(r.err, "16..8192")) << r.err;
  }
  for (const char* time : {"nan", "inf"}) {
    const CommandResult r =
        run_roverlab("gui " + quote(fl) + " --screenshot " + quote(dir.file("g.png")) + " --time " + time);
    EXPECT_EQ(r.exit_code, 2) << time << r.err;
  }
  // The smoother is on by default (issue 30); a method with --no-smoother is the usage error now.
  const CommandResult smoother =
      run_roverlab("estimate contact-angle --no-smoother --smoother-method rts " + quote(fl));
  EXPECT_EQ(smoother.exit_code, 2) << smoother.err;
  EXPECT_TRUE(contains(smoother.err, "--smoother")) << smoother.err;
  for (const char* out : {"out.csv", "out.txt", "out"}) {
    expect_one_line(run_roverlab("estimate contact-angle " + quote(fl) + " -o " + quote(dir.file(out))), 2, out,
                    "OUT.h5");
    expect_one_line(run_roverlab("simulate flat_60s --duration 1 -o " + quote(dir.file(out))), 2, out, "OUT.h5");
    EXPECT_FALSE(fs::exists(dir.file(out)));
  }
  const CommandResult empty = run_roverlab("discrepancy rover " + quote(fl) + " --scenario ''");
  EXPECT_EQ(empty.exit_code, 2) << empty.err;
  EXPECT_TRUE(contains(empty.err, "--scenario")) << empty.err;
  expect_one_line(run_roverlab("simulate flat_60s --duration 1e-9 -o " + quote(dir.file("tiny.h5"))), 2, "--duration",
                  "[0.1, 100000]");
}

// N16: the GUI's --tab Bogus was ignored and a time outside the log shown;
// the rover view drew a blank picture "x = nan m" for an all-NaN pose.
TEST(NewSurfaces, TheGuiAndRenderRefuseWhatTheyCannotShow) {
  TempDir dir;
  const SimulatedLog log(dir, "flat.h5", 10);
  const std::string shot = dir.file("g.png");
  const CommandResult tab = run_roverlab("gui " + quote(log.path()) + " --screenshot " + quote(shot) + " --tab Bogus");
  expect_one_line(tab, 2, "--tab Bogus", "expected one of");
  const CommandResult late = run_roverlab("gui " + quote(log.path()) + " --screenshot " + quote(shot) + " --time 1e9");
  EXPECT_EQ(late.exit_code, 2) << late.err;
  EXPECT_TRUE(contains(late.err, "outside the log")) << late.err;
  EXPECT_FALSE(fs::exists(shot));
  log.edit([](hid_t f) {
    for (const char* c : {"x", "z", "pitch"}) {
      change_values(f, std::string("/streams/truth/pose/channels/") + c, [](std::size_t, double) { return NAN; });
    }
  });
  expect_one_line(run_roverlab("render " + quote(log.path()) + " --view rover -o " + quote(dir.file("r.png"))), 3,
                  log.path(), "has no finite value");
}

// A scenario file: flat_60s with `changes`.
std::string scenario_file(const TempDir& dir, const std::string& name, const nlohmann::json& changes) {
  nlohmann::json doc =
      nlohmann::json::parse(test::read_text(std::string(ROVERLAB_RESOURCES_DIR) + "/scenarios/flat_60s.json"));
  doc["duration_s"] = 2;
  if (changes.is_object()) doc.update(changes);
  const std::string path = dir.file(name);
  test::write_text(path, doc.dump(1));
  return path;
}

// N18, N19, N30, N25: a misspelt key was ignored; bump_x_m 1e300 printed a
// 300-digit number; a duration of 1e-300 s made a 1-sample log; traction
// "bogus" was exit 2 without the file; an unknown soil or rover named no
// scenario; a 100000-character name was blamed on the output; a name with
// terminal escapes was printed raw.
TEST(NewSurfaces, AScenarioFileIsCheckedFieldByField) {
  TempDir dir;
  const struct {
    const char* file;
    nlohmann::json change;
    const char* problem;
  } bad[] = {{"typo.json", {{"path", "slope"}, {"slope_degs", 10}}, "field 'slope_degs': unknown field"},
             {"bump.json", {{"path", "bump"}, {"bump_x_m", 1e300}}, "field 'bump_x_m': must be within +-1000"},
             {"tiny.json", {{"duration_s", 1e-300}}, "field 'duration_s': must be at least 0.1"},
             {"traction.json", {{"traction", "bogus"}}, "field 'traction': 'bogus'"},
             {"soil.json", {{"soil", "nosuch"}}, "field 'soil'"},
             {"rover.json", {{"rover", "nosuch"}}, "field 'rover'"},
             {"long.json", {{"name", std::string(100000, 'x')}}, "field 'name'"},
             {"escape.json", {{"name", "a\nb\x1b[31mred"}}, "is not a plain name"}};
  for (const auto& b : bad) {
    const std::string path = scenario_file(dir, b.file, b.change);
    const CommandResult r = run_roverlab("simulate " + quote(path) + " -o " + quote(dir.file("out.h5")));
    expect_one_line(r, 3, path, b.problem);
    EXPECT_EQ(r.err.find('\x1b'), std::string::npos) << r.err;
    EXPECT_LT(r.err.size(), 400U);
    EXPECT_FALSE(fs::exists(dir.file("out.h5")));
  }
}

// N22: `simulate my.json -o my.json` replaced the scenario by a log.
TEST(NewSurfaces, SimulateNeverReplacesItsScenario) {
  TempDir dir;
  const std::string path = scenario_file(dir, "my.h5", {});
  const std::string before = test::read_text(path);
  expect_one_line(run_roverlab("simulate " + quote(path) + " -o " + quote(path)), 2, path, "that is the input file");
  EXPECT_EQ(test::read_text(path), before);
}

// N29: a random draw on a long fast run gave "effect-start-x must be
// -1000..1000" for an effect the user never gave.
TEST(NewSurfaces, ARandomEffectIsAlwaysAValidOne) {
  TempDir dir;
  const std::string fast = scenario_file(dir, "fast.json", {{"desired_speed_mps", 2}, {"duration_s", 2000}});
  // Seed 2 draws a soil change from 25-65 % of the expected 2800 m.
  const CommandResult r = run_roverlab("simulate " + quote(fast) + " --effect random --seed 2 --duration 2000 -o " +
                                       quote(dir.file("fast.h5")));
  EXPECT_FALSE(contains(r.err, "effect-start-x")) << r.err;
  EXPECT_TRUE(r.exit_code == 0 || r.exit_code == 3) << r.err;
}

// N21: a log's metadata `scenario` was followed as a path (../../etc/passwd
// opened and echoed); a custom scenario named flat_60s was studied against the
// bundled one. Now the scenario is recorded in the log and a name is a name.
TEST(NewSurfaces, ALogsScenarioIsDataNeverAPath) {
  TempDir dir;
  const SimulatedLog log(dir, "flat.h5", 10);
  for (const char* name : {"../../../../etc/passwd", "/etc/hostname", "flat_60s.json"}) {
    const std::string path = log.copy_as(dir, "named.h5");
    edit_file(path, [&](hid_t f) {
      delete_metadata(f, "scenario_json");
      set_metadata(f, "scenario", name);
    });
    const CommandResult r = run_roverlab("discrepancy rover " + quote(path));
    expect_one_line(r, 3, path, "is not a scenario name");
    EXPECT_FALSE(contains(r.err + r.out, "root:")) << r.err;
  }
  // A scenario of the bundled one's name is recorded whole in the log it makes.
  const std::string shadow = scenario_file(dir, "shadow.json", {{"name", "flat_60s"}, {"soil", "dry_sand"}});
  ASSERT_EQ(run_roverlab("simulate " + quote(shadow) + " -o " + quote(dir.file("shadow.h5"))).exit_code, 0);
  const CommandResult info = run_roverlab("info --json " + quote(dir.file("shadow.h5")));
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const nlohmann::json extra = nlohmann::json::parse(info.out).at("metadata").at("extra");
  EXPECT_EQ(nlohmann::json::parse(extra.at("scenario_json").get<std::string>()).at("soil"), "dry_sand");
  // The recorded scenario is the one studied: a broken record is named, not replaced by the bundled flat_60s.
  log.edit([](hid_t f) { set_metadata(f, "scenario_json", "{\"format\": \"roverlab-scenario\", \"kind\": 5}"); });
  expect_one_line(run_roverlab("discrepancy rover " + quote(log.path())), 3, "metadata scenario_json", "kind");
}

// N6: a study against a scenario on another path ran 378 s on a 20 s log.
TEST(NewSurfaces, AStudyAgainstAScenarioOnAnotherPathIsRefusedEarly) {
  TempDir dir;
  const SimulatedLog log(dir, "flat.h5", 10);
  expect_one_line(run_roverlab("discrepancy rover " + quote(log.path()) + " --scenario rolling_200s"), 3, log.path(),
                  "cannot be this run's model");
  // On the same path, a speed set point no candidate changes: refused at
  // once too (it was fitted for minutes).
  nlohmann::json sc =
      nlohmann::json::parse(test::read_text(std::string(ROVERLAB_RESOURCES_DIR) + "/scenarios/flat_60s.json"));
  sc["name"] = "flat_fast";
  sc["desired_speed_mps"] = 0.05;
  test::write_text(dir.file("flat_fast.json"), sc.dump());
  const auto start = std::chrono::steady_clock::now();
  expect_one_line(
      run_roverlab("discrepancy rover " + quote(log.path()) + " --scenario " + quote(dir.file("flat_fast.json"))), 3,
      log.path(), "desired speed 0.02 m/s, not 0.05 m/s); scenario flat_fast cannot be this run's model");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
}

// N23, N28, N18, N34: a log named `...h5` became run `..` (and `rm -rf
// runs/../report` removed the user's report/); `{item}.h5` was read by the
// workflow engine as a pattern; misspelt campaign keys were ignored;
// /dev/null was "no such file".
TEST(NewSurfaces, ACampaignsRunNamesArePlainAndItsFileHasNoUnknownKeys) {
  TempDir dir;
  const SimulatedLog log(dir, "flat.h5", 1);
  fs::create_directories(dir.path() / "dots");
  fs::copy_file(log.path(), dir.path() / "dots" / "...h5");
  // The campaign's items are written for Snakemake (a dry run); without it, this part is skipped.
  if (test::run_command("command -v snakemake").exit_code == 0) {
    const CommandResult dots =
        run_roverlab("campaign " + quote(dir.file("dots")) + " -o " + quote(dir.file("out")) + " -n");
    ASSERT_TRUE(fs::exists(dir.file("out/items.json"))) << dots.err;
    const nlohmann::json items = nlohmann::json::parse(test::read_text(dir.file("out/items.json"))).at("items");
    ASSERT_EQ(items.size(), 1U);
    for (const auto& [name, item] : items.items()) {
      EXPECT_NE(name.front(), '.') << name;
      (void)item;
    }
  }
  fs::create_directories(dir.path() / "braces");
  fs::copy_file(log.path(), dir.path() / "braces" / "{item}.h5");
  expect_one_line(run_roverlab("campaign " + quote(dir.file("braces")) + " -o " + quote(dir.file("out2")) + " -n"), 3,
                  "{item}.h5", "braces");
  const nlohmann::json base = {{"format", "roverlab-campaign"}, {"version", 1}};
  const struct {
    nlohmann::json entry;
    const char* problem;
  } bad[] = {{{{"simulations", {{{"simulate", "flat_60s"}, {"seed", {5, 6}}}}}}, "field 'simulations[0].seed'"},
             {{{"simulations", {{{"simulate", "flat_60s"}, {"effect", nlohmann::json::array({{}})}}}}},
              "field 'simulations[0].effect'"},
             {{{"simulations", {{{"simulate", "flat_60s"}, {"seeds", {{"first", 1}, {"count", 2}, {"step", 2}}}}}}},
              "field 'simulations[0].seeds.step'"},
             {{{"logs", {{{"file", log.path()}, {"mappin", "x"}}}}}, "field 'logs[0].mappin'"},
             {{{"logs", {{{"file", "/dev/null"}}}}}, "not a regular file"},
             {{{"logs", {{{"file", dir.file("dots")}}}}}, "is a folder"},
             // N9: 100000 runs kept Snakemake planning for minutes; at most 10000.
             {{{"simulations", {{{"simulate", "flat_60s"}, {"seeds", {{"first", 1}, {"count", 10001}}}}}}},
              "outside [1, 10000]"}};
  int k = 0;
  for (const auto& b : bad) {
    nlohmann::json doc = base;
    doc.update(b.entry);
    const std::string file = dir.file("c" + std::to_string(k++) + ".json");
    test::write_text(file, doc.dump());
    const CommandResult r = run_roverlab("campaign " + quote(file) + " -o " + quote(dir.file("out3")) + " -n");
    EXPECT_EQ(r.exit_code, 3) << doc.dump() << r.err;
    EXPECT_TRUE(contains(r.err, b.problem)) << r.err;
  }
}

// N31: every new file was 0600 whatever the umask.
TEST(NewSurfaces, NewFilesHonourTheUmask) {
  TempDir dir;
  const std::string out = dir.file("new.h5");
  ASSERT_EQ(
      test::run_command("umask 022 && " + quote(kExe) + " simulate flat_60s --duration 1 -o " + quote(out)).exit_code,
      0);
  struct stat st {};
  ASSERT_EQ(::stat(out.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0644U);
  const std::string tight = dir.file("tight.h5");
  ASSERT_EQ(
      test::run_command("umask 077 && " + quote(kExe) + " simulate flat_60s --duration 1 -o " + quote(tight)).exit_code,
      0);
  ASSERT_EQ(::stat(tight.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600U);
}

// N34: messages that named the wrong cause: a single-wheel table given to net
// traction ("time column 'wheel' has no unit"); the traction view of a log
// holding net-traction estimates ("give a planar rocker-bogie log", though it
// is one); an empty stream "t = nan .. nan". N32: Qt's XDG_RUNTIME_DIR line
// came before RoverLab's one line.
TEST(NewSurfaces, MessagesNameTheRealCause) {
  TempDir dir;
  const std::string table = std::string(ROVERLAB_TEST_DATA) + "/single_wheel/ding2011_tyii.csv";
  expect_one_line(run_roverlab("estimate net-traction " + quote(table)), 3, table, "a single-wheel test table");
  const SimulatedLog log(dir, "flat.h5", 10);
  const std::string estimated = dir.file("estimated.h5");
  ASSERT_EQ(run_roverlab("estimate net-traction " + quote(log.path()) + " -o " + quote(estimated)).exit_code, 0);
  // Since issue 30 the log keeps the estimator's result: the view draws from it. A log written
  // before (estimates without their result) is told what to do.
  const CommandResult drawn =
      run_roverlab("render " + quote(estimated) + " --view traction-surface -o " + quote(dir.file("t.png")));
  EXPECT_EQ(drawn.exit_code, 0) << drawn.err;
  edit_file(estimated, [](hid_t f) { H5Ldelete(f, "/results", H5P_DEFAULT); });
  expect_one_line(
      run_roverlab("render " + quote(estimated) + " --view traction-surface -o " + quote(dir.file("t.png"))), 3,
      estimated, "holds the estimates of `estimate net-traction` but not its result");
  const std::string fl = contact_angle_log(dir, "fl.h5");
  edit_file(fl, [](hid_t f) { cut_stream(f, "wheels", 0); });
  expect_one_line(run_roverlab("estimate contact-angle " + quote(fl)), 3, fl, "stream 'wheels' is empty");
  const std::string missing = dir.file("missing.h5");
  const CommandResult gui = test::run_command("env -u XDG_RUNTIME_DIR timeout 120 " + quote(kExe) + " gui " +
                                              quote(missing) + " --screenshot " + quote(dir.file("g.png")));
  expect_one_line(gui, 3, missing, "no such file");
  EXPECT_EQ(gui.err.rfind("roverlab: ", 0), 0U) << gui.err;
}

// N20: a report written into the folder of another log's report left that
// report's surfaces and tables beside the new one.
TEST(NewSurfaces, AReportReplacesTheReportBeforeIt) {
  TempDir dir;
  const SimulatedLog log(dir, "flat.h5", 10);
  const std::string fl = contact_angle_log(dir, "fl.h5");
  const std::string out = dir.file("report");
  ASSERT_EQ(run_roverlab("report " + quote(log.path()) + " -o " + quote(out)).exit_code, 0);
  ASSERT_TRUE(fs::exists(out + "/surface_drawbar-pull.png"));
  test::write_text(out + "/notes.txt", "the user's own");
  const CommandResult r = run_roverlab("report " + quote(fl) + " -o " + quote(out));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::exists(out + "/surface_drawbar-pull.png"));
  EXPECT_FALSE(fs::exists(out + "/surface_torque.csv"));
  EXPECT_TRUE(fs::exists(out + "/contact_angles.png"));
  EXPECT_TRUE(fs::exists(out + "/notes.txt")) << "only what the old report wrote is removed";
}

// N7: a campaign killed by SIGKILL left Snakemake running, holding the
// folder's lock (the rerun failed with "Directory cannot be locked"). Then
// Snakemake got SIGTERM when RoverLab died, and in about 1 of 7 kills its
// handler deadlocked and it never exited (CI's run of 30 November). Now it
// gets SIGKILL, and the folder's lock is an flock the kernel frees: while a
// run lasts a second is refused, and once it is killed a rerun starts at once.
TEST(NewSurfaces, SnakemakeDiesWithTheCampaign) {
  if (test::run_command("command -v snakemake").exit_code != 0) GTEST_SKIP() << "no snakemake";
  TempDir dir;
  // 100 runs: a campaign far longer than the waits below (8 s for 4 runs on an idle machine, about
  // 200 s for these), so that a Snakemake left running would still be there at their end.
  std::string seeds;
  for (int i = 1; i <= 100; ++i) seeds += (i > 1 ? ", " : "") + std::to_string(i);
  test::write_text(dir.file("c.json"), R"({"format": "roverlab-campaign", "version": 1,
      "simulations": [{"simulate": "flat_60s", "seeds": [)" +
                                           seeds + R"(], "duration": 30}]})");
  const std::string out = dir.file("out");
  const std::string campaign = "env -u DISPLAY " + quote(kExe) + " campaign c.json -o " + quote(out);
  // An orphan is a snakemake of this folder whose parent is now init; the script waits up to 60 s
  // for none to be left (at once: SIGKILL).
  const std::string orphans = "ps -eo pid=,ppid=,args= | awk -v d=" + quote("--directory " + out + " ") +
                              " 'index($0, d) && $2 == 1 {print $1}'";
  const std::string wait_orphans =
      "i=0\nwhile [ $i -lt 60 ] && [ -n \"$(" + orphans + ")\" ]; do sleep 1; i=$((i + 1)); done\n";
  // The first run killed 2 s after it said it started (up to 60 s under load; Snakemake is then
  // running its first steps), a second tried while it runs; then a rerun killed so as well.
  const std::string started =
      "started() { i=0; while [ $i -lt 600 ] && ! grep -q 'campaign: 100 runs' \"$1\"; do sleep 0.1; "
      "i=$((i + 1)); done; sleep 2; }\n";
  test::write_text(dir.file("kill.sh"),
                   "cd " + quote(dir.path().string()) + "\n" + started + campaign +
                       " > log1.txt 2>&1 &\npid=$!\nstarted log1.txt\n" + campaign +
                       " > log2.txt 2>&1\necho $? > rc2.txt\nkill -KILL $pid\nwait $pid\n" + wait_orphans + orphans +
                       "\n" + campaign + " > log3.txt 2>&1 &\npid=$!\nstarted log3.txt\nkill -KILL $pid\nwait $pid\n" +
                       wait_orphans + orphans + "\n");
  const CommandResult killed = test::run_command("sh " + quote(dir.file("kill.sh")));
  EXPECT_TRUE(contains(test::read_text(dir.file("log1.txt")), "campaign: 100 runs"))
      << test::read_text(dir.file("log1.txt"));
  // The second run, while the first ran: refused in one line, exit code 3, nothing started.
  EXPECT_EQ(test::read_text(dir.file("rc2.txt")), "3\n");
  const std::string second = test::read_text(dir.file("log2.txt"));
  EXPECT_TRUE(contains(second, "another `roverlab campaign` is running in this folder")) << second;
  EXPECT_EQ(std::count(second.begin(), second.end(), '\n'), 1) << second;
  // The rerun after the SIGKILL started at once: no lock left behind.
  const std::string third = test::read_text(dir.file("log3.txt"));
  EXPECT_TRUE(contains(third, "campaign: 100 runs")) << third;
  EXPECT_FALSE(contains(third, "another")) << third;
  std::string left = killed.out;
  std::replace(left.begin(), left.end(), '\n', ' ');
  while (!left.empty() && left.back() == ' ') left.pop_back();
  if (!left.empty()) test::run_command("kill -KILL " + left + " 2>/dev/null");  // the orphans' ids, not by name
  EXPECT_TRUE(left.empty()) << "snakemake still running: " << left;
}

}  // namespace
}  // namespace roverlab
