// MCAP files written by the MCAP project's own writer and Foxglove's ROS 1 and
// ROS 2 serialisers (tests/data/mcap/make_fixtures.mjs says how), read back:
// every value equal to what was written, with and without a summary, chunks
// plain, zstd and lz4, a time range read through the chunk indexes, and
// damaged files refused with one line.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/common/error.h"
#include "importers/log_file.h"
#include "importers/mcap_file.h"
#include "kapvik_ros_log.h"
#include "test_support.h"

using namespace roverlab;
using roverlab::test::TempDir;

namespace {

const std::string kData = std::string(ROVERLAB_TEST_DATA) + "/mcap/";

double value(int i, int k) { return 0.1 * i + 1e-7 * k - 3.3; }

std::vector<char> bytes_of(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::string& path, const std::vector<char>& bytes, std::size_t n) {
  std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(n));
}

std::string read_error(const std::string& path, const io::McapSelection& selection = {}) {
  try {
    (void)io::read_mcap(path, {}, selection);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void expect_imu(const log::Stream& s, int count, double step) {
  ASSERT_EQ(s.size(), static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    EXPECT_EQ(s.channel("angular_velocity.x").values[i], value(i, 10));
    EXPECT_EQ(s.channel("angular_velocity.z").values[i], value(i, 12));
    EXPECT_EQ(s.channel("linear_acceleration.y").values[i], value(i, 14));
    EXPECT_EQ(s.channel("orientation_covariance.4").values[i], value(i, 4));
    EXPECT_EQ(s.channel("linear_acceleration_covariance.8").values[i], value(i, 38));
    // JavaScript's Math.sin and glibc's sin may differ in the last bit: 4 ulps.
    EXPECT_DOUBLE_EQ(s.channel("orientation.z").values[i], std::sin(0.05 * i));
    if (i < 30) {
      EXPECT_NEAR(s.channel("orientation.yaw").values[i], 0.1 * i, 1e-12);
    }
    EXPECT_NEAR(s.time()[i], step * i, 1e-9);
  }
}

TEST(Mcap, Ros1MessagesReadBackFromEveryChunkingAndCompression) {
  struct Case {
    const char* file;
    bool indexed;
  };
  for (const Case& c :
       {Case{"imu_ros1_none.mcap", true}, Case{"imu_ros1_zstd.mcap", true}, Case{"imu_ros1_lz4.mcap", true},
        Case{"imu_ros1_zstd_no_summary.mcap", false}, Case{"imu_ros1_unchunked_no_summary.mcap", false}}) {
    SCOPED_TRACE(c.file);
    io::McapReadStats stats;
    const log::Log lg = io::read_mcap(kData + c.file, {}, {}, &stats);
    EXPECT_EQ(stats.indexed, c.indexed);
    expect_imu(lg.stream("imu/data"), 100, 0.01);
    EXPECT_EQ(lg.metadata.extra.at("topic /imu/data"), "sensor_msgs/Imu, 100 messages");
    EXPECT_EQ(lg.metadata.extra.at("time_origin"), "1700000000.250000000");
    EXPECT_EQ(lg.stream("imu/data").channel("header.seq").values[42], 42.0);
  }
  // load_log picks the MCAP reader by the magic bytes, whatever the name.
  TempDir dir;
  const std::string renamed = dir.file("imu.log");
  std::filesystem::copy_file(kData + "imu_ros1_lz4.mcap", renamed);
  EXPECT_EQ(io::load_log(renamed).format, "MCAP");
}

// WrenchStamped, TwistStamped and TFMessage (with JointState and Imu),
// written by the MCAP project's writer (make_kapvik_mcap.mjs) in ROS 1 and
// ROS 2 (CDR) encodings, onto the rover's streams by
// resources/mappings/ros_kapvik.json, as the same data in a bag
// (Ros1Bag.WrenchTwistAndTfMapOntoTheRoversStreams).
TEST(Mcap, WrenchTwistAndTfMapOntoTheRoversStreams) {
  io::LoadOptions o;
  o.mapping = io::load_mapping(std::string(ROVERLAB_RESOURCES_DIR) + "/mappings/ros_kapvik.json");
  for (const char* file : {"kapvik_ros1_zstd.mcap", "kapvik_cdr_lz4_no_summary.mcap"}) {
    SCOPED_TRACE(file);
    const log::Log lg = io::load_log(kData + file, o).log;
    EXPECT_EQ(lg.metadata.rover_id, "kapvik_planar");
    roverlab::test::kapvik::expect_mapped_log(lg);
  }
}

TEST(Mcap, HeaderStampOnRequest) {
  io::LoadOptions o;
  o.header_time = true;
  const log::Log lg = io::read_mcap(kData + "imu_ros1_zstd.mcap", o);
  EXPECT_EQ(lg.metadata.extra.at("time_origin"), "1700000000.253000000");  // stamps are 3 ms after the log times
  expect_imu(lg.stream("imu/data"), 100, 0.01);
}

TEST(Mcap, Ros2CdrAndJsonMessages) {
  const log::Log lg = io::load_log(kData + "rover_cdr_json_lz4.mcap").log;
  const log::Stream& imu = lg.stream("imu");
  ASSERT_EQ(imu.size(), 50U);
  const log::Stream& joints = lg.stream("joint_states");
  const log::Stream& status = lg.stream("status");
  for (int i = 0; i < 50; ++i) {
    EXPECT_EQ(imu.channel("angular_velocity.y").values[i], value(i, 11));
    EXPECT_EQ(imu.channel("linear_acceleration.z").values[i], value(i, 15));
    EXPECT_EQ(imu.channel("angular_velocity_covariance.3").values[i], value(i, 23));
    EXPECT_DOUBLE_EQ(imu.channel("orientation.w").values[i], std::cos(0.05 * i));  // Math.cos vs glibc: 4 ulps
    EXPECT_NEAR(imu.channel("header.stamp").values[i], 1700000000.253 + 0.02 * i, 1e-6);
    EXPECT_NEAR(imu.time()[i], 0.02 * i, 1e-9);
    EXPECT_EQ(joints.channel("position.front_left_wheel").values[i], value(i, 0));
    EXPECT_EQ(joints.channel("position.rear_right_wheel").values[i], value(i, 3));
    EXPECT_EQ(joints.channel("velocity.rear_left_wheel").values[i], value(i, 12));
    EXPECT_EQ(status.channel("battery.voltage").values[i], value(i, 40));
    EXPECT_EQ(status.channel("moving").values[i], i % 2 == 0 ? 1.0 : 0.0);
    EXPECT_EQ(status.channel("temps.1").values[i], value(i, 42));
  }
  EXPECT_EQ(status.find_channel("mode"), nullptr);  // strings are not channels
  for (const auto& c : joints.channels()) EXPECT_EQ(c.name.rfind("effort", 0), std::string::npos) << c.name;
  EXPECT_EQ(lg.metadata.extra.at("topic /joint_states"), "sensor_msgs/msg/JointState, 50 messages");
}

TEST(Mcap, ATimeRangeReadsOnlyTheChunksThatHoldIt) {
  const std::string path = kData + "ranged_zstd.mcap";
  const auto size = std::filesystem::file_size(path);
  io::McapReadStats all;
  const log::Log whole = io::read_mcap(path, {}, {}, &all);
  ASSERT_EQ(whole.stream("imu/data").size(), 1000U);
  // 10 % of the 10 s: messages 450 .. 550.
  io::McapSelection range;
  range.start_ns = 1'700'000'000'250'000'000ULL + 4'500'000'000ULL;
  range.end_ns = 1'700'000'000'250'000'000ULL + 5'500'000'000ULL;
  io::McapReadStats stats;
  const log::Log part = io::read_mcap(path, {}, range, &stats);
  EXPECT_TRUE(stats.indexed);
  const log::Stream& s = part.stream("imu/data");
  ASSERT_EQ(s.size(), 101U);
  EXPECT_EQ(s.channel("header.seq").values.front(), 450.0);
  EXPECT_EQ(s.channel("header.seq").values.back(), 550.0);
  EXPECT_EQ(s.channel("angular_velocity.x").values[7], value(457, 10));
  EXPECT_LE(stats.bytes_read, size / 5) << stats.bytes_read << " of " << size;
  std::printf("10 %% of the time: %llu of %llu bytes read (%.1f %%)\n",
              static_cast<unsigned long long>(stats.bytes_read), static_cast<unsigned long long>(size),
              100.0 * static_cast<double>(stats.bytes_read) / static_cast<double>(size));
  // A topic the file lacks: the summary alone.
  io::McapSelection none;
  none.topics = {"/camera"};
  io::McapReadStats nothing;
  EXPECT_TRUE(io::read_mcap(path, {}, none, &nothing).streams().empty());
  EXPECT_LE(nothing.bytes_read, size / 10);
}

// LoadOptions' topics and time range (seconds after the file's first
// message, what `convert --topics --time` passes): through the chunk indexes
// only the chunks that hold the range are decompressed; a file without a
// summary, scanned, gives the same messages at the same times.
TEST(Mcap, TopicsAndATimeRangeInSecondsReadOnlyTheirChunks) {
  io::LoadOptions o;
  o.topics = {"imu/data"};  // with or without the leading '/'
  o.start_s = 4.5;
  o.end_s = 5.5;
  io::McapReadStats stats;
  const log::Log part = io::read_mcap(kData + "ranged_zstd.mcap", o, {}, &stats);
  EXPECT_TRUE(stats.indexed);
  const log::Stream& s = part.stream("imu/data");
  ASSERT_EQ(s.size(), 101U);
  EXPECT_NEAR(s.time().front(), 4.5, 1e-9);  // the file's clock, not the range's
  EXPECT_NEAR(s.time().back(), 5.5, 1e-9);
  EXPECT_EQ(s.channel("angular_velocity.x").values[0], value(450, 10));
  io::McapReadStats whole;
  (void)io::read_mcap(kData + "ranged_zstd.mcap", {}, {}, &whole);
  EXPECT_EQ(whole.chunks_read, whole.chunks_in_file);
  EXPECT_EQ(stats.chunks_in_file, whole.chunks_in_file);
  EXPECT_LE(stats.chunks_read * 5, whole.chunks_read) << stats.chunks_read << " of " << whole.chunks_read;
  std::printf("1 s of 10 s: %llu of %llu chunks decompressed\n", static_cast<unsigned long long>(stats.chunks_read),
              static_cast<unsigned long long>(whole.chunks_read));

  // Indexed and scanned: the same part.
  o.start_s = 0.2;
  o.end_s = 0.4;
  o.topics = {"/imu/data"};
  const log::Log indexed = io::read_mcap(kData + "imu_ros1_zstd.mcap", o);
  const log::Log scanned = io::read_mcap(kData + "imu_ros1_zstd_no_summary.mcap", o);
  ASSERT_EQ(indexed.stream("imu/data").size(), 21U);
  EXPECT_EQ(indexed.stream("imu/data").time(), scanned.stream("imu/data").time());
  EXPECT_EQ(indexed.stream("imu/data").channel("linear_acceleration.y").values,
            scanned.stream("imu/data").channel("linear_acceleration.y").values);
  EXPECT_EQ(indexed.stream("imu/data").channel("header.seq").values.front(), 20.0);
  // Only an end: from the first message.
  o.start_s.reset();
  EXPECT_EQ(io::read_mcap(kData + "imu_ros1_zstd.mcap", o).stream("imu/data").size(), 41U);
  // A topic the file lacks: one line.
  o.topics = {"/imu/data", "/camera"};
  try {
    (void)io::read_mcap(kData + "imu_ros1_zstd.mcap", o);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), kData + "imu_ros1_zstd.mcap: no topic /camera in the file");
  }
}

// The offset of the first record with `opcode` after the magic, walking the
// data section's records.
std::size_t first_record(const std::vector<char>& bytes, std::uint8_t opcode) {
  std::size_t at = 8;
  while (at + 9 <= bytes.size()) {
    std::uint64_t length = 0;
    std::memcpy(&length, bytes.data() + at + 1, 8);
    if (static_cast<std::uint8_t>(bytes[at]) == opcode) return at;
    at += 9 + length;
  }
  return 0;
}

TEST(McapBadInput, OneLineNamingTheFileAndTheProblem) {
  TempDir dir;
  const std::string path = dir.file("bad.mcap");
  // Truncated anywhere: a clean error, never a crash.
  for (const char* name :
       {"imu_ros1_zstd.mcap", "imu_ros1_zstd_no_summary.mcap", "imu_ros1_unchunked_no_summary.mcap"}) {
    const std::vector<char> bytes = bytes_of(kData + name);
    for (const std::size_t keep : {std::size_t{3}, std::size_t{12}, std::size_t{40}, bytes.size() / 3,
                                   bytes.size() / 2 + 7, bytes.size() - 30, bytes.size() - 1}) {
      SCOPED_TRACE(std::string(name) + " cut at " + std::to_string(keep));
      write_bytes(path, bytes, keep);
      const std::string error = read_error(path);
      EXPECT_EQ(error.rfind(path + ": ", 0), 0U) << error;
      EXPECT_EQ(error.find('\n'), std::string::npos);
    }
  }
  std::vector<char> bytes = bytes_of(kData + "imu_ros1_zstd_no_summary.mcap");
  // Wrong magic.
  std::vector<char> wrong = bytes;
  wrong[1] = 'X';
  write_bytes(path, wrong, wrong.size());
  EXPECT_EQ(read_error(path), path + ": not an MCAP file (no MCAP magic bytes)");
  // A chunk that claims 10 GB.
  std::vector<char> huge = bytes;
  const std::size_t chunk = first_record(huge, 0x06);
  ASSERT_GT(chunk, 0U);
  const std::uint64_t ten_gb = 10'000'000'000ULL;
  std::memcpy(huge.data() + chunk + 1, &ten_gb, 8);
  write_bytes(path, huge, huge.size());
  EXPECT_EQ(read_error(path), path + ": the record at offset " + std::to_string(chunk) +
                                  " (opcode 0x6) claims 10000000000 bytes, more than the file holds (truncated?)");
  // An unknown compression: "zstd" becomes "zzzz" in the chunks (the
  // summary's chunk indexes name it too, but its CRC would refuse them).
  std::vector<char> unknown = bytes_of(kData + "imu_ros1_zstd.mcap");
  std::uint64_t summary_start = 0;
  std::memcpy(&summary_start, unknown.data() + unknown.size() - 8 - 20, 8);
  for (std::size_t k = 0; k + 4 <= summary_start; ++k) {
    if (std::memcmp(unknown.data() + k, "zstd", 4) == 0) std::memcpy(unknown.data() + k, "zzzz", 4);
  }
  write_bytes(path, unknown, unknown.size());
  EXPECT_EQ(read_error(path), path + ": chunk compression 'zzzz' is not supported (RoverLab reads none, lz4 and zstd)");
  // An encoding RoverLab does not read.
  const std::string protobuf = kData + "unknown_encoding.mcap";
  EXPECT_EQ(read_error(protobuf), protobuf +
                                      ": topic /thing: message encoding 'protobuf' with schema encoding "
                                      "'protobuf' is not supported (RoverLab reads ros1 with ros1msg, cdr with "
                                      "ros2msg, json)");
}

// One byte changed where only the CRC-32s can see it (a value's last byte, a
// schema name's first letter): the chunk's, the summary's and the data
// section's CRC each refuse the file with one line. Without the checks each
// of these files reads, with one value or name wrong.
TEST(McapBadInput, ACrcMismatchNamesTheFileAndWhatIsDamaged) {
  TempDir dir;
  const std::string path = dir.file("damaged.mcap");
  // A chunk (uncompressed, so the byte changed is a value's): its last byte.
  std::vector<char> bytes = bytes_of(kData + "imu_ros1_none.mcap");
  const std::size_t chunk = first_record(bytes, 0x06);
  ASSERT_GT(chunk, 0U);
  std::uint64_t records = 0;
  std::memcpy(&records, bytes.data() + chunk + 9 + 32, 8);
  std::uint64_t chunk_start = 0;
  std::memcpy(&chunk_start, bytes.data() + chunk + 9, 8);
  ASSERT_EQ(bytes[chunk + 9 + 28], 0);  // no compression: an empty string
  bytes[chunk + 9 + 40 + records - 1] ^= 0x01;
  write_bytes(path, bytes, bytes.size());
  std::string error = read_error(path);
  EXPECT_EQ(
      error.rfind(path + ": a chunk of messages from " + std::to_string(chunk_start) + " ns is damaged (its CRC-32 is ",
                  0),
      0U)
      << error;
  EXPECT_EQ(error.find('\n'), std::string::npos);

  // The summary: the first letter of its first record's name (a Schema's).
  bytes = bytes_of(kData + "imu_ros1_zstd.mcap");
  std::uint64_t summary_start = 0;
  std::memcpy(&summary_start, bytes.data() + bytes.size() - 8 - 20, 8);
  ASSERT_GT(summary_start, 0U);
  ASSERT_EQ(bytes[summary_start], 0x03);
  ASSERT_EQ(bytes[summary_start + 9 + 2 + 4], 's');  // sensor_msgs/Imu
  bytes[summary_start + 9 + 2 + 4] = 't';
  write_bytes(path, bytes, bytes.size());
  error = read_error(path);
  EXPECT_EQ(error.rfind(path + ": the summary section is damaged (its CRC-32 is ", 0), 0U) << error;

  // The data section of a file without chunks or summary: a message's last byte.
  bytes = bytes_of(kData + "imu_ros1_unchunked_no_summary.mcap");
  const std::size_t message = first_record(bytes, 0x05);
  ASSERT_GT(message, 0U);
  std::uint64_t length = 0;
  std::memcpy(&length, bytes.data() + message + 1, 8);
  bytes[message + 9 + length - 1] ^= 0x01;
  write_bytes(path, bytes, bytes.size());
  error = read_error(path);
  EXPECT_EQ(error.rfind(path + ": the data section is damaged (its CRC-32 is ", 0), 0U) << error;

  // The files as written read, and give the counts of the chunks they read.
  io::McapReadStats stats;
  EXPECT_EQ(io::read_mcap(kData + "imu_ros1_none.mcap", {}, {}, &stats).stream("imu/data").size(), 100U);
  EXPECT_TRUE(stats.indexed);
  EXPECT_GT(stats.chunks_read, 0U);
  EXPECT_EQ(stats.chunks_read, stats.chunks_in_file);
}

}  // namespace
