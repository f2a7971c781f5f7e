// A ROS 1 bag made from the bundled WVU Pathfinder log (the ROS library's own
// writer, the message headers ROS generates), and the same log as an MCAP file
// of the MCAP project's writer, run through the command line as the MATLAB
// file does: `info` lists their topics, `estimate ins-slip` and `discrepancy
// odometry` give the same answers, bad bags exit 3 with one line.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/NavSatFix.h>

#include "importers/hdf5_log.h"
#include "importers/log_file.h"
#include "test_support.h"

using namespace roverlab;
using nlohmann::json;
using roverlab::test::CommandResult;
using roverlab::test::quote;
using roverlab::test::run_command;
using roverlab::test::TempDir;

namespace {

const std::string kExe = ROVERLAB_EXE;
const std::string kPathfinder = std::string(ROVERLAB_TEST_DATA) + "/test17run.mat";

CommandResult run_roverlab(const std::string& args) { return run_command(quote(kExe) + " " + args); }

// A recorder's clock: some Unix time plus the log's seconds, to the nanosecond.
ros::Time stamp(double t) {
  const auto ns = static_cast<std::int64_t>(std::llround(t * 1e9)) + 1'650'000'000'000'000'000LL;
  ros::Time out;
  out.fromNSec(static_cast<std::uint64_t>(ns));
  return out;
}

// The Pathfinder log as a rover running ROS would have recorded it, laid out
// as resources/mappings/ros_pathfinder.json says.
void write_pathfinder_bag(const log::Log& lg, const std::string& path,
                          rosbag::compression::CompressionType compression) {
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  bag.setCompression(compression);
  const log::Stream& imu = lg.stream("imu");
  const log::Stream& wheels = lg.stream("wheels");
  const log::Stream& gps = lg.stream("gps");
  const log::Stream& odometry = lg.stream("odometry");
  // Messages go in in time order, as a recorder writes them.
  std::size_t i = 0;
  std::size_t w = 0;
  while (i < imu.size() || w < wheels.size()) {
    if (i < imu.size() && (w >= wheels.size() || imu.time()[i] <= wheels.time()[w])) {
      sensor_msgs::Imu m;
      m.header.stamp = stamp(imu.time()[i]);
      m.header.seq = static_cast<std::uint32_t>(i);
      m.orientation_covariance[0] = -1;  // no orientation
      m.linear_acceleration.x = imu.channel("specific_force_x").values[i];
      m.linear_acceleration.y = imu.channel("specific_force_y").values[i];
      m.linear_acceleration.z = imu.channel("specific_force_z").values[i];
      m.angular_velocity.x = imu.channel("angular_rate_x").values[i];
      m.angular_velocity.y = imu.channel("angular_rate_y").values[i];
      m.angular_velocity.z = imu.channel("angular_rate_z").values[i];
      bag.write("/imu/data", m.header.stamp, m);
      ++i;
      continue;
    }
    const ros::Time t = stamp(wheels.time()[w]);
    sensor_msgs::JointState joints;
    joints.header.stamp = t;
    joints.name = {"front_left_wheel", "front_right_wheel", "rear_left_wheel", "rear_right_wheel"};
    for (const char* wheel : {"FL", "FR", "RL", "RR"}) {
      joints.position.push_back(wheels.channel(std::string("angle_") + wheel).values[w]);
    }
    bag.write("/joint_states", t, joints);
    // GPS and odometry share the wheels' time base in this log.
    sensor_msgs::NavSatFix fix;
    fix.header.stamp = t;
    fix.latitude = gps.channel("latitude").values[w] * 180.0 / M_PI;
    fix.longitude = gps.channel("longitude").values[w] * 180.0 / M_PI;
    fix.altitude = gps.channel("height").values[w];
    bag.write("/navsat/fix", t, fix);
    nav_msgs::Odometry local;
    local.header.stamp = t;
    local.pose.pose.position.x = gps.channel("east").values[w];
    local.pose.pose.position.y = gps.channel("north").values[w];
    local.pose.pose.position.z = gps.channel("up").values[w];
    local.pose.pose.orientation.w = 1.0;
    bag.write("/odometry/gps", t, local);
    nav_msgs::Odometry odom;
    odom.header.stamp = t;
    odom.pose.pose.position.x = odometry.channel("x").values[w];
    odom.pose.pose.position.y = odometry.channel("y").values[w];
    odom.pose.pose.orientation.w = 1.0;
    odom.twist.twist.linear.x = odometry.channel("forward_speed").values[w];
    odom.twist.twist.angular.z = odometry.channel("yaw_rate").values[w];
    bag.write("/odom", t, odom);
    ++w;
  }
  bag.close();
}

// Numbers equal within `tolerance` (relative, and absolute near zero),
// everything else exactly; "file" entries name different files. The bag's
// times are whole nanoseconds and its latitudes went through degrees, so
// inputs differ from the MATLAB file's in the last bits: estimates agree to
// 1e-6, but a fitted parameter's sigma (the curvature of a likelihood
// profile, taken by finite differences) moves more, up to 1e-3.
void expect_same(const json& a, const json& b, double tolerance, const std::string& where = "") {
  if (a.is_number() && b.is_number()) {
    const double x = a.get<double>();
    const double y = b.get<double>();
    const double allowed = where.find("sigma") != std::string::npos ? std::max(tolerance, 1e-3) : tolerance;
    EXPECT_LE(std::abs(x - y), allowed * std::max({1.0, std::abs(x), std::abs(y)}))
        << where << ": " << x << " vs " << y;
    return;
  }
  ASSERT_EQ(a.type(), b.type()) << where;
  if (a.is_object()) {
    ASSERT_EQ(a.size(), b.size()) << where;
    for (auto it = a.begin(); it != a.end(); ++it) {
      // "input": the fingerprint of the log's bits, which a bag's nanosecond times change.
      if (it.key() == "file" || it.key() == "log" || it.key() == "source_file" || it.key() == "input") continue;
      ASSERT_TRUE(b.contains(it.key())) << where << "/" << it.key();
      expect_same(it.value(), b.at(it.key()), tolerance, where + "/" + it.key());
    }
  } else if (a.is_array()) {
    ASSERT_EQ(a.size(), b.size()) << where;
    for (std::size_t k = 0; k < a.size(); ++k) expect_same(a[k], b[k], tolerance, where + "/" + std::to_string(k));
  } else {
    EXPECT_EQ(a, b) << where;
  }
}

class PathfinderBag : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    io::LoadOptions options;
    options.mapping = io::load_mapping(std::string(ROVERLAB_RESOURCES_DIR) + "/mappings/wvu_pathfinder.json");
    const log::Log lg = io::load_log(kPathfinder, options).log;
    bag_ = dir_->file("pathfinder.bag");
    write_pathfinder_bag(lg, bag_, rosbag::compression::LZ4);
  }
  static void TearDownTestSuite() { delete dir_; }
  static TempDir* dir_;
  static std::string bag_;
};
TempDir* PathfinderBag::dir_ = nullptr;
std::string PathfinderBag::bag_;

TEST_F(PathfinderBag, InfoListsTopicsTypesCountsAndRates) {
  const CommandResult r = run_roverlab("info " + quote(bag_) + " --json");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j.at("format"), "ROS 1 bag");
  EXPECT_EQ(j.at("metadata").at("extra").at("topic /imu/data"), "sensor_msgs/Imu, 17611 messages");
  EXPECT_EQ(j.at("metadata").at("extra").at("topic /joint_states"), "sensor_msgs/JointState, 705 messages");
  EXPECT_EQ(j.at("metadata").at("extra").at("topic /navsat/fix"), "sensor_msgs/NavSatFix, 705 messages");
  bool found = false;
  for (const auto& s : j.at("streams")) {
    if (s.at("name") != "imu/data") continue;
    found = true;
    EXPECT_EQ(s.at("samples"), 17611);
    EXPECT_NEAR(s.at("rate_hz").get<double>(), 250.0, 1.0);
    EXPECT_NEAR(s.at("duration_s").get<double>(), 70.44, 0.01);
  }
  EXPECT_TRUE(found) << r.out;
}

TEST_F(PathfinderBag, InsSlipAndOdometryDiscrepancyGiveTheMatlabFilesAnswers) {
  for (const std::string command : {"estimate ins-slip", "discrepancy odometry"}) {
    SCOPED_TRACE(command);
    const CommandResult mat = run_roverlab(command + " " + quote(kPathfinder) + " -m wvu_pathfinder --json");
    ASSERT_EQ(mat.exit_code, 0) << mat.err;
    const CommandResult bag = run_roverlab(command + " " + quote(bag_) + " -m ros_pathfinder --json");
    ASSERT_EQ(bag.exit_code, 0) << bag.err;
    expect_same(json::parse(mat.out), json::parse(bag.out), 1e-6);
  }
}

TEST_F(PathfinderBag, ConvertWritesTheMappedStreamsToHdf5) {
  const std::string out = dir_->file("from_bag.h5");
  const CommandResult r = run_roverlab("convert " + quote(bag_) + " " + quote(out) + " -m ros_pathfinder");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const log::Log h5 = io::load_log(out).log;
  const log::Log bag = io::load_log(bag_,
                                    [] {
                                      io::LoadOptions o;
                                      o.mapping = io::load_mapping(std::string(ROVERLAB_RESOURCES_DIR) +
                                                                   "/mappings/ros_pathfinder.json");
                                      return o;
                                    }())
                           .log;
  ASSERT_EQ(h5.streams().size(), 4U);
  for (const auto& s : bag.streams()) {
    const log::Stream& t = h5.stream(s.name());
    EXPECT_EQ(t.time(), s.time());
    for (const auto& c : s.channels()) EXPECT_EQ(t.channel(c.name).values.size(), c.values.size());
  }
}

// The same log as an MCAP file written by the MCAP project's writer
// (tests/data/mcap/make_wvu_mcap.mjs: the topics above, ROS 1 encoding, zstd
// chunks, the times to the nanosecond).
TEST(WvuMcap, InsSlipAndOdometryDiscrepancyGiveTheMatlabFilesAnswers) {
  const std::string mcap = std::string(ROVERLAB_TEST_DATA) + "/mcap/wvu_pathfinder_ros1.mcap";
  const CommandResult info = run_roverlab("info " + quote(mcap) + " --json");
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_EQ(json::parse(info.out).at("metadata").at("extra").at("topic /imu/data"), "sensor_msgs/Imu, 17611 messages");
  for (const std::string command : {"estimate ins-slip", "discrepancy odometry"}) {
    SCOPED_TRACE(command);
    const CommandResult mat = run_roverlab(command + " " + quote(kPathfinder) + " -m wvu_pathfinder --json");
    ASSERT_EQ(mat.exit_code, 0) << mat.err;
    const CommandResult r = run_roverlab(command + " " + quote(mcap) + " -m ros_pathfinder --json");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    expect_same(json::parse(mat.out), json::parse(r.out), 1e-6);
  }
}

// A simulated ExoMars BB2 run (seed 000's flying-rover scenario) as a rover
// running ROS records it (the ROS library's writer): the IMU on /imu/data, and
// every joint (bogies, steering, drives) in one sensor_msgs/JointState on
// /joint_states, as resources/mappings/ros_exomars_bb2.json says.
void write_bb2_bag(const log::Log& lg, const std::string& path) {
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  bag.setCompression(rosbag::compression::LZ4);
  const log::Stream& imu = lg.stream("imu");
  const log::Stream& joints = lg.stream("joints");
  const log::Stream& wheels = lg.stream("wheels");
  ASSERT_EQ(joints.time(), imu.time());
  ASSERT_EQ(wheels.time(), imu.time());
  const char* const wheel_names[] = {"FL", "ML", "RL", "RR", "MR", "FR"};
  for (std::size_t i = 0; i < imu.size(); ++i) {
    const ros::Time t = stamp(imu.time()[i]);
    sensor_msgs::Imu m;
    m.header.stamp = t;
    m.orientation_covariance[0] = -1;
    m.linear_acceleration.x = imu.channel("specific_force_x").values[i];
    m.linear_acceleration.y = imu.channel("specific_force_y").values[i];
    m.linear_acceleration.z = imu.channel("specific_force_z").values[i];
    m.angular_velocity.x = imu.channel("angular_rate_x").values[i];
    m.angular_velocity.y = imu.channel("angular_rate_y").values[i];
    m.angular_velocity.z = imu.channel("angular_rate_z").values[i];
    bag.write("/imu/data", t, m);
    sensor_msgs::JointState js;
    js.header.stamp = t;
    for (const auto& c : joints.channels()) {
      if (c.name.size() > 5 && c.name.compare(c.name.size() - 5, 5, "_rate") == 0) continue;
      js.name.push_back(c.name);
      js.position.push_back(c.values[i]);
      js.velocity.push_back(joints.channel(c.name + "_rate").values[i]);
    }
    for (const char* w : wheel_names) {
      js.name.push_back(std::string("wheel_") + w);
      js.position.push_back(0.0);
      js.velocity.push_back(wheels.channel(std::string("rate_") + w).values[i]);
    }
    bag.write("/joint_states", t, js);
  }
  bag.close();
}

// `estimate contact-angle` (seed 000) on that bag through the mapping gives
// what it gives on the same sensor streams in a RoverLab HDF5 log: every
// number of its JSON to 1e-6 (the bag's times are whole nanoseconds), and the
// same estimated contact angles.
TEST(Bb2Bag, ContactAngleGivesTheHdf5LogsAnswer) {
  TempDir dir;
  const std::string sim = dir.file("sim.h5");
  ASSERT_EQ(run_roverlab("scenario fl-bogie-rotation --rate 100 -o " + quote(sim)).exit_code, 0);
  const log::Log full = io::read_hdf5_log(sim);
  // The sensors alone, as the bag has them (no truth).
  log::Log sensors;
  sensors.metadata.rover_id = full.metadata.rover_id;
  for (const char* s : {"imu", "joints", "wheels"}) sensors.add_stream(full.stream(s));
  const std::string h5 = dir.file("sensors.h5");
  io::write_hdf5_log(sensors, h5);
  const std::string bag = dir.file("bb2.bag");
  write_bb2_bag(full, bag);

  const std::string options = " --model c --reset-cross-covariance --json";
  const std::string est_h5 = dir.file("est_h5.h5");
  const std::string est_bag = dir.file("est_bag.h5");
  const CommandResult a = run_roverlab("estimate contact-angle " + quote(h5) + options + " -o " + quote(est_h5));
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const CommandResult b =
      run_roverlab("estimate contact-angle " + quote(bag) + " -m ros_exomars_bb2" + options + " -o " + quote(est_bag));
  ASSERT_EQ(b.exit_code, 0) << b.err;
  // The estimated contact angles, sample by sample.
  const log::Log ea = io::read_hdf5_log(est_h5);
  const log::Log eb = io::read_hdf5_log(est_bag);
  const log::Stream& wa = ea.stream("estimate/contact/wheels");
  const log::Stream& wb = eb.stream("estimate/contact/wheels");
  ASSERT_EQ(wa.size(), full.stream("imu").size());
  ASSERT_EQ(wb.size(), wa.size());
  for (const char* w : {"FL", "ML", "RL", "RR", "MR", "FR"}) {
    const auto& x = wa.channel(std::string("contact_angle_") + w).values;
    const auto& y = wb.channel(std::string("contact_angle_") + w).values;
    double worst = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) worst = std::max(worst, std::abs(x[i] - y[i]));
    EXPECT_LT(worst, 1e-6) << w;
  }
  // The front-left bogie turned: its wheel's contact angle moved.
  const auto& fl = wb.channel("contact_angle_FL").values;
  EXPECT_GT(*std::max_element(fl.begin(), fl.end()) - *std::min_element(fl.begin(), fl.end()), 0.1);
  json from_h5 = json::parse(a.out);
  json from_bag = json::parse(b.out);
  EXPECT_EQ(from_bag.at("rover"), "exomars_bb2");
  from_h5.erase("wall_seconds");  // how long it took
  from_bag.erase("wall_seconds");
  from_h5.erase("output");  // the two -o files
  from_bag.erase("output");
  expect_same(from_h5, from_bag, 1e-6);
  // Without the mapping the bag has no imu, joints or wheels stream: refused.
  EXPECT_EQ(run_roverlab("estimate contact-angle " + quote(bag) + options).exit_code == 0, false);
}

// `info` and `convert` with --topics and --time START:END (seconds after the
// file's first message): a part of an MCAP file (read through its chunk
// indexes) and of a bag; misuse is one line, exit 2 (a bad option) or 3 (a
// topic the file lacks).
TEST(RosPartCli, InfoAndConvertReadATopicSubsetAndATimeRange) {
  TempDir dir;
  const std::string mcap = std::string(ROVERLAB_TEST_DATA) + "/mcap/ranged_zstd.mcap";
  const std::string out = dir.file("part.h5");
  const CommandResult c =
      run_roverlab("convert " + quote(mcap) + " " + quote(out) + " --topics /imu/data --time 4.5:5.5");
  ASSERT_EQ(c.exit_code, 0) << c.err;
  const log::Log part = io::read_hdf5_log(out);
  ASSERT_EQ(part.stream("imu/data").size(), 101U);
  EXPECT_NEAR(part.stream("imu/data").time().front(), 4.5, 1e-9);
  EXPECT_EQ(part.stream("imu/data").channel("header.seq").values.back(), 550.0);

  const std::string wvu = std::string(ROVERLAB_TEST_DATA) + "/mcap/wvu_pathfinder_ros1.mcap";
  const CommandResult info = run_roverlab("info " + quote(wvu) + " --topics /imu/data,/odom --time 10:20 --json");
  ASSERT_EQ(info.exit_code, 0) << info.err;
  const json doc = json::parse(info.out);
  ASSERT_EQ(doc.at("streams").size(), 2U);
  for (const auto& s : doc.at("streams")) {
    EXPECT_TRUE(s.at("name") == "imu/data" || s.at("name") == "odom") << s.at("name");
    EXPECT_GE(s.at("start_s").get<double>(), 10.0);
    EXPECT_LE(s.at("end_s").get<double>(), 20.0);
    EXPECT_GT(s.at("duration_s").get<double>(), 9.5);
  }

  // A bag, through a mapping: only the mapped topics' range.
  const std::string sim = dir.file("sim.h5");
  ASSERT_EQ(run_roverlab("scenario fl-bogie-rotation --rate 100 -o " + quote(sim)).exit_code, 0);
  const std::string bag = dir.file("bb2.bag");
  write_bb2_bag(io::read_hdf5_log(sim), bag);
  const CommandResult mapped = run_roverlab("info " + quote(bag) + " -m ros_exomars_bb2 --time :2 --json");
  ASSERT_EQ(mapped.exit_code, 0) << mapped.err;
  EXPECT_EQ(json::parse(mapped.out).at("streams").at(0).at("samples"), 201);

  const auto one_line = [](const CommandResult& r) { return std::count(r.err.begin(), r.err.end(), '\n') <= 2; };
  const CommandResult missing = run_roverlab("info " + quote(mcap) + " --topics /camera");
  EXPECT_EQ(missing.exit_code, 3);
  EXPECT_NE(missing.err.find(mcap + ": no topic /camera in the file"), std::string::npos) << missing.err;
  const CommandResult backwards = run_roverlab("info " + quote(mcap) + " --time 5:4");
  EXPECT_EQ(backwards.exit_code, 2);
  EXPECT_TRUE(one_line(backwards)) << backwards.err;
  EXPECT_EQ(run_roverlab("info " + quote(mcap) + " --time ten:20").exit_code, 2);
  EXPECT_EQ(run_roverlab("info " + quote(sim) + " --time 1:2").exit_code, 2);
}

TEST(RosBagCli, BadBagsExitThreeWithOneLine) {
  TempDir dir;
  const std::string fake = dir.file("fake.bag");
  roverlab::test::write_text(fake, "#ROSBAG V2.0\n\x01\x02garbage");
  const CommandResult r = run_roverlab("info " + quote(fake));
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_EQ(r.err.rfind("roverlab: " + fake + ": ", 0), 0U) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

}  // namespace
