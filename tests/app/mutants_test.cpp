// Single-byte mutants of real and simulated RoverLab logs, ROS 1 bags and MCAP
// files, each read whole by
// `roverlab convert` as a user would: every one is read (exit 0) or refused in
// one line (exit 3); none crashes, hangs or is an internal error (issue 17).
// ROVERLAB_MUTANTS sets how many per log (default 40, the CI subset);
// scripts/mutants runs thousands and docs/robustness.md has its figures.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <random>
#include <string>

#include <rosbag/bag.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>

#include "test_support.h"

namespace roverlab {
namespace {

using test::CommandResult;
using test::quote;
using test::TempDir;

const std::string kExe = ROVERLAB_EXE;
const std::string kData = ROVERLAB_TEST_DATA;

CommandResult run_roverlab(const std::string& args) {
  return test::run_command("timeout 20 " + quote(kExe) + " " + args);
}

int mutants_per_log() {
  const char* n = std::getenv("ROVERLAB_MUTANTS");
  return n != nullptr ? std::max(1, std::atoi(n)) : 40;
}

// Mutates one byte at a time: half of them in the first 4 KiB, where HDF5's
// superblock and root object headers live (the crashes of F31/F32 were there),
// half anywhere. Returns the mutants that failed, as "offset=value: reason".
std::vector<std::string> mutate_and_read(const std::string& log, unsigned seed, const std::string& extension = ".h5") {
  const std::string original = test::read_text(log);
  std::mt19937 random(seed);
  std::uniform_int_distribution<int> byte(0, 255);
  TempDir dir;
  const std::string mutant = dir.file("mutant" + extension), out = dir.file("out.h5");
  std::vector<std::string> failures;
  const int n = mutants_per_log();
  for (int i = 0; i < n; ++i) {
    const std::size_t span = i % 2 == 0 ? std::min<std::size_t>(4096, original.size()) : original.size();
    const std::size_t offset = std::uniform_int_distribution<std::size_t>(0, span - 1)(random);
    std::string bytes = original;
    auto value = static_cast<char>(byte(random));
    if (value == bytes[offset]) value = static_cast<char>(~value);
    bytes[offset] = value;
    test::write_text(mutant, bytes);
    const CommandResult r = run_roverlab("convert " + quote(mutant) + " " + quote(out));
    const std::string where = std::to_string(offset) + "=" + std::to_string(static_cast<unsigned char>(value));
    const bool one_line = r.err.empty() || r.err.find('\n') == r.err.size() - 1;
    if (r.exit_code != 0 && r.exit_code != 3) {
      failures.push_back(where + ": exit " + std::to_string(r.exit_code) + " " + r.err);
    } else if (!one_line || (r.exit_code == 3 && r.err.rfind("roverlab: ", 0) != 0)) {
      failures.push_back(where + ": not one line: " + r.err);
    }
  }
  return failures;
}

TEST(Mutants, OfTheBundledFieldLogAreReadOrRefusedInOneLine) {
  TempDir dir;
  const std::string log = dir.file("wvu.h5");
  ASSERT_EQ(
      run_roverlab("convert " + quote(kData + "/test17run.mat") + " " + quote(log) + " -m wvu_pathfinder").exit_code,
      0);
  const auto failures = mutate_and_read(log, 17);
  EXPECT_TRUE(failures.empty()) << failures.size() << " of " << mutants_per_log() << ", first: " << failures.front();
}

TEST(Mutants, OfASimulatedRockerBogieLogAreReadOrRefusedInOneLine) {
  TempDir dir;
  const std::string log = dir.file("sim.h5");
  ASSERT_EQ(run_roverlab("simulate flat_60s --duration 5 -o " + quote(log)).exit_code, 0);
  const auto failures = mutate_and_read(log, 5);
  EXPECT_TRUE(failures.empty()) << failures.size() << " of " << mutants_per_log() << ", first: " << failures.front();
}

// Bags written by the ROS library's own writer: LZ4 and BZ2 chunks.
TEST(Mutants, OfRosBagsAreReadOrRefusedInOneLine) {
  TempDir dir;
  for (const auto compression : {rosbag::compression::LZ4, rosbag::compression::BZ2}) {
    const std::string log = dir.file("rover.bag");
    {
      rosbag::Bag bag(log, rosbag::bagmode::Write);
      bag.setCompression(compression);
      bag.setChunkThreshold(2048);
      for (int i = 0; i < 60; ++i) {
        const ros::Time t(1'700'000'000 + i / 10, (i % 10) * 100'000'000);
        sensor_msgs::Imu imu;
        imu.header.stamp = t;
        imu.angular_velocity.x = 0.1 * i;
        imu.orientation.w = 1.0;
        bag.write("/imu/data", t, imu);
        sensor_msgs::JointState joints;
        joints.header.stamp = t;
        joints.name = {"FL", "FR"};
        joints.position = {0.01 * i, -0.01 * i};
        bag.write("/joint_states", t, joints);
      }
    }
    const auto failures = mutate_and_read(log, compression == rosbag::compression::LZ4 ? 31 : 32, ".bag");
    EXPECT_TRUE(failures.empty()) << failures.size() << " of " << mutants_per_log() << ", first: " << failures.front();
  }
}

// MCAP files of the MCAP project's writer (tests/data/mcap): indexed (lz4,
// ROS 2 CDR and JSON) and unindexed (zstd, ROS 1).
TEST(Mutants, OfMcapFilesAreReadOrRefusedInOneLine) {
  for (const char* name : {"rover_cdr_json_lz4.mcap", "imu_ros1_zstd_no_summary.mcap"}) {
    const auto failures = mutate_and_read(kData + "/mcap/" + name, 33, ".mcap");
    EXPECT_TRUE(failures.empty()) << name << ": " << failures.size() << " of " << mutants_per_log()
                                  << ", first: " << failures.front();
  }
}

// Single-byte mutants of a text document at `target` (uniform over the
// file), each given to `command`: exit 0 or one line and exit 3, never a
// crash, a hang (20 s) or an internal error. The original is put back.
// `environment`: assignments put before the command (e.g. PATH=...).
std::vector<std::string> mutate_document(const std::string& target, unsigned seed, const std::string& command,
                                         const std::string& environment = "") {
  const std::string original = test::read_text(target);
  std::mt19937 random(seed);
  std::uniform_int_distribution<int> byte(0, 255);
  std::vector<std::string> failures;
  for (int i = 0; i < mutants_per_log(); ++i) {
    const std::size_t offset = std::uniform_int_distribution<std::size_t>(0, original.size() - 1)(random);
    std::string bytes = original;
    auto value = static_cast<char>(byte(random));
    if (value == bytes[offset]) value = static_cast<char>(~value);
    bytes[offset] = value;
    test::write_text(target, bytes);
    const CommandResult r = test::run_command(environment + " timeout 20 " + quote(kExe) + " " + command);
    const std::string where = std::to_string(offset) + "=" + std::to_string(static_cast<unsigned char>(value));
    const bool one_line = r.err.empty() || r.err.find('\n') == r.err.size() - 1;
    if (r.exit_code != 0 && r.exit_code != 3) {
      failures.push_back(where + ": exit " + std::to_string(r.exit_code) + " " + r.err);
    } else if (!one_line || (r.exit_code == 3 && r.err.rfind("roverlab: ", 0) != 0)) {
      failures.push_back(where + ": not one line: " + r.err);
    }
  }
  test::write_text(target, original);
  return failures;
}

// Issue 34 item 6: scenario files as `simulate` reads them (every bundled
// one), and the run documents `campaign report` reads (run.json, and the
// report/metrics.json that `roverlab report` wrote).
TEST(Mutants, OfScenarioFilesAreSimulatedOrRefusedInOneLine) {
  TempDir dir;
  const std::string scenario = dir.file("scenario.json");
  unsigned seed = 41;
  for (const char* name : {"flat_60s", "rolling_200s", "slope_5deg", "bump_crossing"}) {
    test::write_text(scenario, test::read_text(std::string(ROVERLAB_RESOURCES_DIR) + "/scenarios/" + name + ".json"));
    const auto failures = mutate_document(
        scenario, seed++, "simulate " + quote(scenario) + " --duration 0.2 -o " + quote(dir.file("o.h5")));
    EXPECT_TRUE(failures.empty()) << name << ": " << failures.size() << " of " << mutants_per_log()
                                  << ", first: " << failures.front();
  }
}

TEST(Mutants, OfACampaignRunsDocumentsAreReportedOrRefusedInOneLine) {
  TempDir dir;
  const std::string run = dir.file("runs/sim");
  ASSERT_EQ(run_roverlab("simulate flat_60s --duration 10 -o " + quote(dir.file("sim.h5"))).exit_code, 0);
  const CommandResult report = test::run_command("timeout 120 " + quote(kExe) + " report " + quote(dir.file("sim.h5")) +
                                                 " -o " + quote(run + "/report"));
  ASSERT_EQ(report.exit_code, 0) << report.err;
  test::write_text(run + "/run.json", R"({"format": "roverlab-campaign-run", "name": "sim", "kind": "simulate",
    "scenario": "flat_60s", "seed": 1, "effects": {"gyro-bias": 0.01}, "roverlab_version": "test"})");
  const std::string command = "campaign report " + quote(run) + " -o " + quote(dir.file("out"));
  ASSERT_EQ(run_roverlab(command).exit_code, 0);
  unsigned seed = 51;
  for (const std::string document : {"/run.json", "/report/metrics.json"}) {
    const auto failures = mutate_document(run + document, seed++, command);
    EXPECT_TRUE(failures.empty()) << document << ": " << failures.size() << " of " << mutants_per_log()
                                  << ", first: " << failures.front();
  }
}

// Campaign files as `roverlab campaign FILE -o DIR -n` reads them: every
// field of docs/campaigns.md (a folder and a file of logs, a mapping,
// flying-rover and skid-steer scenarios with seed lists and ranges, a rate,
// a steering manoeuvre with a slip angle, simulate runs with a duration and
// effect sets), and the two bundled
// campaign files without paths. RoverLab reads and checks the whole file and
// writes DIR/items.json before Snakemake starts; a stub `snakemake` that
// does nothing stands in for it (the workflow engine is not under test, and
// its start would cost a second a mutant).
TEST(Mutants, OfCampaignFilesArePlannedOrRefusedInOneLine) {
  TempDir dir;
  std::filesystem::create_directories(dir.file("logs"));
  std::filesystem::create_directories(dir.file("stub"));
  ASSERT_EQ(run_roverlab("simulate flat_60s --duration 2 -o " + quote(dir.file("logs/sim.h5"))).exit_code, 0);
  test::write_text(dir.file("stub/snakemake"), "#!/bin/sh\nexit 0\n");
  ASSERT_EQ(test::run_command("chmod +x " + quote(dir.file("stub/snakemake"))).exit_code, 0);
  const std::string environment = "PATH=" + quote(dir.file("stub")) + ":\"$PATH\"";
  const std::string every_field = R"({
  "format": "roverlab-campaign",
  "version": 1,
  "name": "every-field",
  "description": "the fields of docs/campaigns.md",
  "logs": [
    {"folder": "logs"},
    {"file": "logs/sim.h5", "mapping": "wvu_pathfinder"}
  ],
  "simulations": [
    {"scenario": "skid-steer-slip", "seeds": {"first": 1, "count": 4},
     "effects": [{"slip": 0}, {"slip": 0, "left-radius-scale": 1.05}]},
    {"scenario": "fl-bogie-rotation", "seeds": [1, 2, 3], "rate": 200},
    {"scenario": "flat-turn", "seeds": [1], "rate": 200, "turn_radius": 1.5, "slip_angle_deg": 2,
     "slip_angle_from": 10},
    {"simulate": "flat_60s", "seeds": [1], "duration": 20, "effects": [{}, {"soil-strength": 0.8}]}
  ]
}
)";
  const std::string campaigns = std::string(ROVERLAB_RESOURCES_DIR) + "/../workflows/campaigns/";
  const std::string file = dir.file("campaign.json");
  const std::string command = "campaign " + quote(file) + " -o " + quote(dir.file("out")) + " -n";
  unsigned seed = 61;
  for (const std::string name : {"every-field", "timing-200", "contact-angle-noise-50"}) {
    test::write_text(file, name == "every-field" ? every_field : test::read_text(campaigns + name + ".json"));
    const CommandResult original = test::run_command(environment + " " + quote(kExe) + " " + command);
    ASSERT_EQ(original.exit_code, 0) << name << ": " << original.err;
    const auto failures = mutate_document(file, seed++, command, environment);
    EXPECT_TRUE(failures.empty()) << name << ": " << failures.size() << " of " << mutants_per_log()
                                  << ", first: " << failures.front();
  }
}

}  // namespace
}  // namespace roverlab
