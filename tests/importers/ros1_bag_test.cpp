// ROS 1 bags: written here by the ROS library's own writer (rosbag::Bag) with
// the message headers ROS generates (their definitions and serialisers are
// ROS's, not RoverLab's), read back through load_log: every value equal to
// what was written, bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <geometry_msgs/TwistStamped.h>
#include <geometry_msgs/WrenchStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/NavSatFix.h>
#include <tf2_msgs/TFMessage.h>

#include <nlohmann/json.hpp>

#include "core/common/error.h"
#include "importers/log_file.h"
#include "importers/ros_msg_decoder.h"
#include "importers/ros_standard_units.h"
#include "kapvik_ros_log.h"
#include "raw_ros_message.h"
#include "test_support.h"

using namespace roverlab;
using roverlab::test::RawRosMessage;
using roverlab::test::TempDir;
using roverlab::test::write_text;

namespace {

const ros::Time kStart(1'700'000'000, 250'000'000);

ros::Time at(double seconds) { return kStart + ros::Duration(seconds); }

double value(int i, int k) { return 0.1 * i + 1e-7 * k - 3.3; }

sensor_msgs::Imu imu_message(int i) {
  sensor_msgs::Imu m;
  m.header.seq = static_cast<std::uint32_t>(i);
  m.header.stamp = at(0.01 * i + 0.003);  // sensor time, 3 ms after the record time
  m.header.frame_id = "imu_link";
  const double roll = 0.1 + 0.001 * i;
  const double pitch = -0.2;
  const double yaw = 0.3 - 0.002 * i;
  // ZYX: q = qz(yaw) qy(pitch) qx(roll)
  const double cr = std::cos(roll / 2), sr = std::sin(roll / 2);
  const double cp = std::cos(pitch / 2), sp = std::sin(pitch / 2);
  const double cy = std::cos(yaw / 2), sy = std::sin(yaw / 2);
  m.orientation.w = cr * cp * cy + sr * sp * sy;
  m.orientation.x = sr * cp * cy - cr * sp * sy;
  m.orientation.y = cr * sp * cy + sr * cp * sy;
  m.orientation.z = cr * cp * sy - sr * sp * cy;
  for (int k = 0; k < 9; ++k) m.orientation_covariance[k] = value(i, k);
  m.angular_velocity.x = value(i, 10);
  m.angular_velocity.y = value(i, 11);
  m.angular_velocity.z = value(i, 12);
  m.linear_acceleration.x = value(i, 13);
  m.linear_acceleration.y = value(i, 14);
  m.linear_acceleration.z = value(i, 15);
  return m;
}

void write_imu_bag(const std::string& path, rosbag::compression::CompressionType compression, int count = 200) {
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  bag.setCompression(compression);
  bag.setChunkThreshold(4096);  // many chunks
  for (int i = 0; i < count; ++i) bag.write("/imu/data", at(0.01 * i), imu_message(i));
  bag.close();
}

io::LoadOptions options(bool header_time = false, std::size_t max_array = 64) {
  io::LoadOptions o;
  o.header_time = header_time;
  o.max_array = max_array;
  return o;
}

std::string load_error(const std::string& path, const io::LoadOptions& o = {}) {
  try {
    (void)io::load_log(path, o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void expect_imu_values(const log::Log& lg, int count) {
  const log::Stream& s = lg.stream("imu/data");
  ASSERT_EQ(s.size(), static_cast<std::size_t>(count));
  for (int i = 0; i < count; ++i) {
    const sensor_msgs::Imu m = imu_message(i);
    EXPECT_EQ(s.channel("angular_velocity.x").values[i], m.angular_velocity.x);
    EXPECT_EQ(s.channel("angular_velocity.z").values[i], m.angular_velocity.z);
    EXPECT_EQ(s.channel("linear_acceleration.y").values[i], m.linear_acceleration.y);
    EXPECT_EQ(s.channel("orientation.w").values[i], m.orientation.w);
    EXPECT_EQ(s.channel("orientation_covariance.8").values[i], m.orientation_covariance[8]);
    EXPECT_EQ(s.channel("header.seq").values[i], i);
    EXPECT_NEAR(s.channel("orientation.roll").values[i], 0.1 + 0.001 * i, 1e-12);
    EXPECT_NEAR(s.channel("orientation.pitch").values[i], -0.2, 1e-12);
    EXPECT_NEAR(s.channel("orientation.yaw").values[i], 0.3 - 0.002 * i, 1e-12);
    EXPECT_NEAR(s.time()[i], 0.01 * i, 1e-9);
  }
}

TEST(Ros1Bag, ImuValuesReadBackBitForBitFromEveryChunkCompression) {
  TempDir dir;
  for (const auto& [name, compression] :
       {std::pair{"plain", rosbag::compression::Uncompressed}, std::pair{"bz2", rosbag::compression::BZ2},
        std::pair{"lz4", rosbag::compression::LZ4}}) {
    SCOPED_TRACE(name);
    const std::string path = dir.file(std::string(name) + ".bag");
    write_imu_bag(path, compression);
    const io::LoadedLog loaded = io::load_log(path, options());
    EXPECT_EQ(loaded.format, "ROS 1 bag");
    expect_imu_values(loaded.log, 200);
    EXPECT_EQ(loaded.log.metadata.extra.at("topic /imu/data"), "sensor_msgs/Imu, 200 messages");
    EXPECT_EQ(loaded.log.metadata.extra.at("time_origin"), "1700000000.250000000");
    // No string channel (frame_id); header.stamp is a time in seconds.
    EXPECT_EQ(loaded.log.stream("imu/data").find_channel("header.frame_id"), nullptr);
    EXPECT_EQ(loaded.log.stream("imu/data").channel("header.stamp").unit, "s");
  }
}

TEST(Ros1Bag, RecordTimeByDefaultHeaderStampOnRequest) {
  TempDir dir;
  const std::string path = dir.file("stamped.bag");
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    for (int i = 0; i < 20; ++i) {
      sensor_msgs::Imu m = imu_message(i);
      m.header.stamp = at(0.5 + 0.02 * i * i);  // sensor time: not the recorder's
      bag.write("/imu/data", at(1.0 + 0.1 * i), m);
    }
  }
  const log::Log record = io::load_log(path, options(false)).log;
  const log::Log header = io::load_log(path, options(true)).log;
  EXPECT_EQ(record.metadata.extra.at("time_origin"), "1700000001.250000000");
  EXPECT_EQ(header.metadata.extra.at("time_origin"), "1700000000.750000000");
  for (int i = 0; i < 20; ++i) {
    EXPECT_NEAR(record.stream("imu/data").time()[i], 0.1 * i, 1e-9);
    EXPECT_NEAR(header.stream("imu/data").time()[i], 0.02 * i * i, 1e-9);
  }
  EXPECT_EQ(header.metadata.extra.at("time"), "header");
}

// The bag's chunks are read record by record, in file order
// (importers/ros1_bag_chunks.h); the library's View hands out messages in
// record-time order. A topic whose record times go back in the file is read
// through the View; topics come in the order of their first record times.
TEST(Ros1Bag, RecordTimesGoingBackInTheFileStillReadInTimeOrder) {
  TempDir dir;
  const std::string path = dir.file("backwards.bag");
  geometry_msgs::TwistStamped late;
  late.twist.linear.x = 7.0;
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    bag.setChunkThreshold(1024);           // several chunks, their time ranges overlapping
    bag.write("/cmd_vel", at(2.0), late);  // first in the file, last in time
    for (int i = 0; i < 40; ++i) bag.write("/imu/data", at(0.01 * (39 - i)), imu_message(39 - i));
  }
  const log::Log lg = io::load_log(path, options()).log;
  ASSERT_EQ(lg.streams().size(), 2U);
  EXPECT_EQ(lg.streams()[0].name(), "imu/data");  // its first record time comes first
  EXPECT_EQ(lg.streams()[1].name(), "cmd_vel");
  expect_imu_values(lg, 40);
  EXPECT_NEAR(lg.stream("cmd_vel").time()[0], 2.0, 1e-9);

  // In order within each topic (the chunk loop's case), the topics still in
  // the order of their first record times, not the file's.
  const std::string forwards = dir.file("forwards.bag");
  {
    rosbag::Bag bag(forwards, rosbag::bagmode::Write);
    bag.write("/cmd_vel", at(2.0), late);
    for (int i = 0; i < 40; ++i) bag.write("/imu/data", at(0.01 * i), imu_message(i));
  }
  const log::Log in_order = io::load_log(forwards, options()).log;
  ASSERT_EQ(in_order.streams().size(), 2U);
  EXPECT_EQ(in_order.streams()[0].name(), "imu/data");
  expect_imu_values(in_order, 40);
}

TEST(Ros1Bag, JointStateArraysSplitByNamesAndEmptyArraysGiveNoChannels) {
  TempDir dir;
  const std::string path = dir.file("joints.bag");
  const std::vector<std::string> names = {"front_left_wheel", "front_right_wheel", "rear/left", "rear_right_wheel"};
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    for (int i = 0; i < 30; ++i) {
      sensor_msgs::JointState m;
      m.header.stamp = at(0.1 * i);
      m.name = names;
      for (int k = 0; k < 4; ++k) {
        m.position.push_back(value(i, k));
        m.velocity.push_back(value(i, 10 + k));
      }
      // From message 20 on, a fifth joint (a steering joint) joins.
      if (i >= 20) {
        m.name.push_back("steer");
        m.position.push_back(value(i, 4));
        m.velocity.push_back(value(i, 14));
      }
      bag.write("/joint_states", at(0.1 * i), m);
    }
  }
  const log::Log lg = io::load_log(path).log;
  const log::Stream& s = lg.stream("joint_states");
  ASSERT_EQ(s.size(), 30U);
  for (int i = 0; i < 30; ++i) {
    EXPECT_EQ(s.channel("position.front_left_wheel").values[i], value(i, 0));
    EXPECT_EQ(s.channel("position.rear_left").values[i], value(i, 2));  // '/' cannot be in a channel name
    EXPECT_EQ(s.channel("velocity.rear_right_wheel").values[i], value(i, 13));
    if (i < 20) {
      EXPECT_TRUE(std::isnan(s.channel("position.steer").values[i]));
    } else {
      EXPECT_EQ(s.channel("position.steer").values[i], value(i, 4));
    }
  }
  for (const auto& c : s.channels()) EXPECT_EQ(c.name.rfind("effort", 0), std::string::npos) << c.name;
}

// Every mapped message type (and a JointState and an IMU): the rover's bag.
void write_rover_bag(const std::string& path) {
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  bag.setCompression(rosbag::compression::LZ4);
  for (int i = 0; i < 10; ++i) {
    sensor_msgs::NavSatFix fix;
    fix.header.stamp = at(0.1 * i);
    fix.latitude = 39.6 + value(i, 0) * 1e-5;
    fix.longitude = -79.9 + value(i, 1) * 1e-5;
    fix.altitude = value(i, 2);
    fix.status.status = 2;
    fix.position_covariance_type = 1;
    bag.write("/navsat/fix", at(0.1 * i), fix);
    geometry_msgs::WrenchStamped w;
    w.wrench.force.x = value(i, 3);
    w.wrench.torque.z = value(i, 4);
    bag.write("/wheel_fl/wrench", at(0.1 * i), w);
    geometry_msgs::TwistStamped tw;
    tw.twist.linear.x = value(i, 5);
    tw.twist.angular.z = value(i, 6);
    bag.write("/cmd_vel", at(0.1 * i), tw);
    nav_msgs::Odometry odom;
    odom.pose.pose.position.x = value(i, 7);
    odom.pose.pose.orientation.w = 1.0;
    odom.pose.covariance[35] = value(i, 8);
    odom.twist.twist.linear.x = value(i, 9);
    odom.child_frame_id = "base_link";
    bag.write("/odom", at(0.1 * i), odom);
    tf2_msgs::TFMessage tf;
    for (int k = 0; k < 2; ++k) {
      geometry_msgs::TransformStamped t;
      t.header.stamp = at(0.1 * i);
      t.child_frame_id = k == 0 ? "base_link" : "mast";
      t.transform.translation.x = value(i, 20 + k);
      t.transform.rotation.w = 1.0;
      tf.transforms.push_back(t);
    }
    bag.write("/tf", at(0.1 * i), tf);
    bag.write("/imu/data", at(0.1 * i), imu_message(i));
    sensor_msgs::JointState joints;
    joints.header.stamp = at(0.1 * i);
    joints.name = {"front_left_wheel", "steer/front"};
    joints.position = {value(i, 30), value(i, 31)};
    joints.effort = {value(i, 32), value(i, 33)};
    bag.write("/joint_states", at(0.1 * i), joints);
  }
  bag.close();
}

TEST(Ros1Bag, EveryMappedMessageTypeDecodes) {
  TempDir dir;
  const std::string path = dir.file("rover.bag");
  write_rover_bag(path);
  const log::Log lg = io::load_log(path).log;
  for (int i = 0; i < 10; ++i) {
    EXPECT_EQ(lg.stream("navsat/fix").channel("latitude").values[i], (39.6 + value(i, 0) * 1e-5) * (M_PI / 180.0));
    EXPECT_EQ(lg.stream("navsat/fix").channel("altitude").values[i], value(i, 2));
    EXPECT_EQ(lg.stream("navsat/fix").channel("status.status").values[i], 2.0);
    EXPECT_EQ(lg.stream("navsat/fix").channel("position_covariance_type").values[i], 1.0);
    EXPECT_EQ(lg.stream("wheel_fl/wrench").channel("wrench.force.x").values[i], value(i, 3));
    EXPECT_EQ(lg.stream("wheel_fl/wrench").channel("wrench.torque.z").values[i], value(i, 4));
    EXPECT_EQ(lg.stream("cmd_vel").channel("twist.linear.x").values[i], value(i, 5));
    EXPECT_EQ(lg.stream("cmd_vel").channel("twist.angular.z").values[i], value(i, 6));
    EXPECT_EQ(lg.stream("odom").channel("pose.pose.position.x").values[i], value(i, 7));
    EXPECT_EQ(lg.stream("odom").channel("pose.covariance.35").values[i], value(i, 8));
    EXPECT_EQ(lg.stream("odom").channel("twist.twist.linear.x").values[i], value(i, 9));
    EXPECT_EQ(lg.stream("odom").channel("pose.pose.orientation.yaw").values[i], 0.0);
    EXPECT_EQ(lg.stream("tf").channel("transforms.base_link.transform.translation.x").values[i], value(i, 20));
    EXPECT_EQ(lg.stream("tf").channel("transforms.mast.transform.translation.x").values[i], value(i, 21));
    EXPECT_EQ(lg.stream("tf").channel("transforms.mast.header.stamp").values[i], at(0.1 * i).toSec());
  }
  // Arrays longer than the limit are skipped whole: the covariances (9 and
  // 36) and the two transforms go, the scalars stay.
  const log::Log small = io::load_log(path, options(false, 1)).log;
  EXPECT_EQ(small.stream("odom").find_channel("pose.covariance.0"), nullptr);
  EXPECT_EQ(small.stream("navsat/fix").find_channel("position_covariance.0"), nullptr);
  EXPECT_EQ(small.stream("tf").channels().size(), 0U);
  EXPECT_EQ(small.stream("tf").size(), 10U);
  EXPECT_EQ(small.stream("odom").channel("pose.pose.position.x").values[3], value(3, 7));
}

// Standard messages get their REP 103 units without a mapping (issue 44): forces in N and joint angles in rad
// no longer share one unitless axis.
TEST(Ros1Bag, StandardMessagesGetTheirUnits) {
  TempDir dir;
  const std::string path = dir.file("rover.bag");
  write_rover_bag(path);
  const log::Log lg = io::load_log(path).log;
  const auto unit = [&](const char* stream, const char* channel) { return lg.stream(stream).channel(channel).unit; };
  EXPECT_EQ(unit("wheel_fl/wrench", "wrench.force.x"), "N");
  EXPECT_EQ(unit("wheel_fl/wrench", "wrench.torque.z"), "N*m");
  EXPECT_EQ(unit("cmd_vel", "twist.linear.x"), "m/s");
  EXPECT_EQ(unit("cmd_vel", "twist.angular.z"), "rad/s");
  EXPECT_EQ(unit("odom", "pose.pose.position.x"), "m");
  EXPECT_EQ(unit("odom", "pose.pose.orientation.yaw"), "rad");
  EXPECT_EQ(unit("odom", "pose.pose.orientation.w"), "1");  // a quaternion part
  EXPECT_EQ(unit("odom", "twist.twist.linear.x"), "m/s");
  EXPECT_EQ(unit("odom", "pose.covariance.35"), "1");
  EXPECT_EQ(unit("tf", "transforms.mast.transform.translation.x"), "m");
  EXPECT_EQ(unit("tf", "transforms.mast.transform.rotation.yaw"), "rad");
  EXPECT_EQ(unit("tf", "transforms.mast.header.stamp"), "s");
  EXPECT_EQ(unit("navsat/fix", "latitude"), "rad");
  EXPECT_EQ(unit("navsat/fix", "altitude"), "m");
  EXPECT_EQ(unit("navsat/fix", "position_covariance.0"), "m^2");
  EXPECT_EQ(unit("navsat/fix", "status.status"), "1");
  EXPECT_EQ(unit("imu/data", "angular_velocity.x"), "rad/s");
  EXPECT_EQ(unit("imu/data", "linear_acceleration.z"), "m/s^2");
  EXPECT_EQ(unit("joint_states", "position.front_left_wheel"), "rad");
  EXPECT_EQ(unit("joint_states", "effort.front_left_wheel"), "N*m");
  // ROS 2 type names and the untyped Vector3.
  EXPECT_EQ(io::ros::standard_unit("geometry_msgs/msg/PoseStamped", "pose.position.z")->unit, "m");
  EXPECT_EQ(io::ros::standard_unit("sensor_msgs/JointState", "velocity.elbow_joint")->unit, "rad/s");
  EXPECT_FALSE(io::ros::standard_unit("geometry_msgs/Vector3Stamped", "vector.x").has_value());
  EXPECT_FALSE(io::ros::standard_unit("geometry_msgs/Wrench", "wrench.force.x").has_value());
}

// The shipped wheel-rig mapping (issue 44): a wrench above the wheel, the
// wheel's joint and the carriage's twist become forces, wheels and carriage.
TEST(Ros1Bag, TheWheelRigMappingReadsARigsBag) {
  TempDir dir;
  const std::string path = dir.file("rig.bag");
  {
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    for (int i = 0; i < 20; ++i) {
      geometry_msgs::WrenchStamped w;
      w.wrench.force.x = value(i, 1);
      w.wrench.force.y = value(i, 2);
      w.wrench.force.z = value(i, 3);
      w.wrench.torque.y = value(i, 4);
      bag.write("/wheel/wrench", at(0.05 * i), w);
      sensor_msgs::JointState js;
      js.name = {"wheel"};
      js.position = {value(i, 5)};
      js.velocity = {value(i, 6)};
      bag.write("/joint_states", at(0.05 * i), js);
      geometry_msgs::TwistStamped tw;
      tw.twist.linear.x = value(i, 7);
      bag.write("/carriage/twist", at(0.05 * i), tw);
    }
  }
  io::LoadOptions o;
  o.mapping = io::load_mapping(std::string(ROVERLAB_RESOURCES_DIR) + "/mappings/ros_wheel_rig.json");
  const log::Log lg = io::load_log(path, o).log;
  const log::Stream& forces = lg.stream("forces");
  ASSERT_EQ(forces.size(), 20U);
  EXPECT_EQ(forces.channel("drawbar_pull").unit, "N");
  EXPECT_EQ(forces.channel("resistive_torque").unit, "N*m");
  EXPECT_EQ(lg.stream("wheels").channel("rate").unit, "rad/s");
  EXPECT_EQ(lg.stream("carriage").channel("speed").unit, "m/s");
  for (int i = 0; i < 20; ++i) {
    EXPECT_EQ(forces.channel("drawbar_pull").values[i], value(i, 1));
    EXPECT_EQ(forces.channel("normal_load").values[i], value(i, 3));
    EXPECT_EQ(forces.channel("resistive_torque").values[i], value(i, 4));
    EXPECT_EQ(lg.stream("wheels").channel("angle").values[i], value(i, 5));
    EXPECT_EQ(lg.stream("carriage").channel("speed").values[i], value(i, 7));
  }
}

TEST(Ros1Bag, AMappingNamesTopicsAsRoverStreamsWithUnits) {
  TempDir dir;
  const std::string bag_path = dir.file("imu.bag");
  write_imu_bag(bag_path, rosbag::compression::BZ2, 50);
  const std::string mapping = dir.file("m.json");
  write_text(mapping, R"({"format": "roverlab-mapping", "version": 1, "name": "ros_test", "rover_id": "r",
    "streams": [{"name": "imu", "time": {"variable": "/imu/data", "unit": "s"},
      "channels": [{"name": "angular_rate_x", "variable": "/imu/data/angular_velocity.x", "unit": "deg/s"},
                   {"name": "specific_force_z", "variable": "/imu/data/linear_acceleration.z", "unit": "m/s^2", "scale": -1}]}]})");
  io::LoadOptions o;
  o.mapping = io::load_mapping(mapping);
  const log::Log lg = io::load_log(bag_path, o).log;
  ASSERT_EQ(lg.streams().size(), 1U);
  const log::Stream& s = lg.stream("imu");
  ASSERT_EQ(s.size(), 50U);
  EXPECT_EQ(s.channel("angular_rate_x").unit, "rad/s");
  for (int i = 0; i < 50; ++i) {
    EXPECT_DOUBLE_EQ(s.channel("angular_rate_x").values[i], value(i, 10) * M_PI / 180.0);
    EXPECT_EQ(s.channel("specific_force_z").values[i], -value(i, 15));
  }
  EXPECT_EQ(lg.metadata.rover_id, "r");

  // A field the topic lacks, and a topic the bag lacks: named.
  write_text(mapping, R"({"format": "roverlab-mapping", "version": 1, "name": "ros_test",
    "streams": [{"name": "imu", "time": {"variable": "/imu/data", "unit": "s"},
      "channels": [{"name": "x", "variable": "/imu/data/angular_velocity.w", "unit": "rad/s"}]}]})");
  o.mapping = io::load_mapping(mapping);
  EXPECT_EQ(load_error(bag_path, o), bag_path +
                                         ": mapping ros_test: channel imu/x: topic /imu/data (sensor_msgs/Imu) "
                                         "has no numeric field angular_velocity.w");
  write_text(mapping, R"({"format": "roverlab-mapping", "version": 1, "name": "ros_test",
    "streams": [{"name": "imu", "time": {"variable": "/imu", "unit": "s"}, "channels": []}]})");
  o.mapping = io::load_mapping(mapping);
  EXPECT_EQ(load_error(bag_path, o), bag_path + ": mapping ros_test: no topic /imu in the file");
}

// A planar rocker-bogie's log as tests/importers/kapvik_ros_log.h describes
// it, written by the ROS library's own writer with the message classes ROS
// generates.
void write_kapvik_bag(const std::string& path, rosbag::compression::CompressionType compression) {
  namespace k = roverlab::test::kapvik;
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  bag.setCompression(compression);
  for (int i = 0; i < k::kMessages; ++i) {
    ros::Time t = kStart;
    t += ros::Duration().fromNSec(std::int64_t{50'000'000} * i);
    sensor_msgs::Imu imu;
    imu.header.stamp = t;
    imu.linear_acceleration.x = k::value(i, 0);
    imu.linear_acceleration.z = k::value(i, 2);
    imu.angular_velocity.y = k::value(i, 4);
    imu.orientation.w = 1.0;
    bag.write("/imu/data", t, imu);
    sensor_msgs::JointState joints;
    joints.header.stamp = t;
    joints.name = {"wheel_1", "bogie", "wheel_2", "wheel_3"};
    for (int j = 0; j < 4; ++j) joints.position.push_back(k::value(i, 10 + j));
    bag.write("/joint_states", t, joints);
    sensor_msgs::JointState commands;
    commands.header.stamp = t;
    commands.name = {"wheel_1", "wheel_2", "wheel_3"};
    for (int j = 0; j < 3; ++j) commands.effort.push_back(k::value(i, 20 + j));
    bag.write("/joint_commands", t, commands);
    geometry_msgs::TwistStamped twist;
    twist.header.stamp = t;
    twist.twist.linear.x = k::value(i, 30);
    twist.twist.angular.y = k::value(i, 31);
    bag.write("/velocimeter", t, twist);
    for (int w = 0; w < 3; ++w) {
      geometry_msgs::WrenchStamped wrench;
      wrench.header.stamp = t;
      wrench.header.frame_id = "wheel_" + std::to_string(w + 1);
      wrench.wrench.force.x = k::value(i, 40 + w);
      wrench.wrench.force.z = k::value(i, 50 + w);
      wrench.wrench.torque.y = k::value(i, 60 + w);
      bag.write("/wheel_" + std::to_string(w + 1) + "/wrench", t, wrench);
    }
    tf2_msgs::TFMessage tf;
    geometry_msgs::TransformStamped mast;
    mast.header.stamp = t;
    mast.header.frame_id = "base_link";
    mast.child_frame_id = "mast";
    mast.transform.translation.x = k::value(i, 79);
    mast.transform.rotation.w = 1.0;
    geometry_msgs::TransformStamped base;
    base.header.stamp = t;
    base.header.frame_id = "odom";
    base.child_frame_id = "base_link";
    base.transform.translation.x = k::value(i, 70);
    base.transform.translation.y = k::value(i, 71);
    base.transform.translation.z = k::value(i, 72);
    base.transform.rotation.y = std::sin(k::pitch(i) / 2);
    base.transform.rotation.w = std::cos(k::pitch(i) / 2);
    if (!k::has_base_link(i)) {
      tf.transforms = {mast};
    } else if (i % 2 == 1) {
      tf.transforms = {mast, base};
    } else {
      tf.transforms = {base, mast};
    }
    bag.write("/tf", t, tf);
  }
  bag.close();
}

// geometry_msgs/WrenchStamped, TwistStamped and tf2_msgs/TFMessage (with
// JointState and Imu) onto the rover's forces, velocimeter, pose, joints,
// commands and imu streams by resources/mappings/ros_kapvik.json, with units,
// value for value; the transforms named by their child_frame_id.
TEST(Ros1Bag, WrenchTwistAndTfMapOntoTheRoversStreams) {
  TempDir dir;
  io::LoadOptions o;
  o.mapping = io::load_mapping(std::string(ROVERLAB_RESOURCES_DIR) + "/mappings/ros_kapvik.json");
  for (const auto compression : {rosbag::compression::Uncompressed, rosbag::compression::LZ4}) {
    const std::string path = dir.file("kapvik" + std::to_string(static_cast<int>(compression)) + ".bag");
    write_kapvik_bag(path, compression);
    const log::Log lg = io::load_log(path, o).log;
    EXPECT_EQ(lg.metadata.rover_id, "kapvik_planar");
    roverlab::test::kapvik::expect_mapped_log(lg);
  }
  // Without a mapping: each transform's channels named by its frame.
  const log::Log raw = io::load_log(dir.file("kapvik0.bag")).log;
  const log::Stream& tf = raw.stream("tf");
  EXPECT_EQ(tf.channel("transforms.mast.transform.translation.x").values[1], roverlab::test::kapvik::value(1, 79));
  EXPECT_EQ(tf.channel("transforms.base_link.transform.translation.x").values[1], roverlab::test::kapvik::value(1, 70));
  EXPECT_TRUE(std::isnan(tf.channel("transforms.base_link.transform.translation.x").values[3]));
  EXPECT_EQ(tf.find_channel("transforms.0.transform.translation.x"), nullptr);
}

// LoadOptions' topics and time range on a bag: the library's view of those
// connections and record times, times from the bag's first message.
TEST(Ros1Bag, TopicsAndATimeRangeInSeconds) {
  namespace k = roverlab::test::kapvik;
  TempDir dir;
  const std::string path = dir.file("kapvik.bag");
  write_kapvik_bag(path, rosbag::compression::LZ4);
  io::LoadOptions o;
  o.topics = {"/imu/data", "tf"};
  o.start_s = 0.5;
  o.end_s = 1.0;
  const log::Log lg = io::load_log(path, o).log;
  ASSERT_EQ(lg.streams().size(), 2U);
  const log::Stream& imu = lg.stream("imu/data");
  ASSERT_EQ(imu.size(), 11U);  // messages 10 .. 20
  EXPECT_NEAR(imu.time().front(), 0.5, 1e-9);
  EXPECT_NEAR(imu.time().back(), 1.0, 1e-9);
  EXPECT_EQ(imu.channel("linear_acceleration.x").values[0], k::value(10, 0));
  EXPECT_EQ(lg.stream("tf").size(), 11U);
  o.topics = {"/imu/data", "/camera"};
  EXPECT_EQ(load_error(path, o), path + ": no topic /camera in the file");
}

// Debian's python3-rosbag decodes the same bag with classes genpy generates
// from the bag's own definitions (tests/importers/rosbag_numeric_fields.py):
// every numeric field it finds is a channel, value for value, and every
// channel is such a field (or a quaternion's roll, pitch, yaw).
TEST(Ros1Bag, ChannelsEqualWhatPythonRosbagDecodes) {
  if (test::run_command("/usr/bin/python3 -c 'import rosbag, genpy'").exit_code != 0) {
    GTEST_SKIP() << "Debian's python3-rosbag is not installed (scripts/install-deps installs it)";
  }
  TempDir dir;
  const std::string path = dir.file("rover.bag");
  write_rover_bag(path);
  const std::string script = std::string(ROVERLAB_TEST_SOURCE_DIR) + "/importers/rosbag_numeric_fields.py";
  const test::CommandResult py = test::run_command("/usr/bin/python3 " + test::quote(script) + " " + test::quote(path));
  ASSERT_EQ(py.exit_code, 0) << py.err;
  const nlohmann::json fields = nlohmann::json::parse(py.out);
  const log::Log lg = io::load_log(path).log;
  std::size_t compared = 0;
  for (const auto& [topic, columns] : fields.items()) {
    const log::Stream& s = lg.stream(topic.substr(1));
    const std::string& type_and_count = lg.metadata.extra.at("topic " + topic);
    const std::string type = type_and_count.substr(0, type_and_count.find(','));
    for (const auto& [name, values] : columns.items()) {
      const log::Channel* c = s.find_channel(name);
      ASSERT_NE(c, nullptr) << topic << " " << name;
      ASSERT_EQ(c->values.size(), values.size()) << topic << " " << name;
      // NavSatFix's degrees come in rad (the standard units, issue 44).
      const auto unit = io::ros::standard_unit(type, name);
      const double factor = unit ? unit->factor : 1.0;
      for (std::size_t i = 0; i < values.size(); ++i) {
        EXPECT_EQ(c->values[i], values[i].get<double>() * factor) << topic << " " << name << " [" << i << "]";
        ++compared;
      }
    }
    for (const auto& c : s.channels()) {
      const auto ends_with = [&](const std::string& tail) {
        return c.name.size() > tail.size() && c.name.compare(c.name.size() - tail.size(), tail.size(), tail) == 0;
      };
      const bool derived = ends_with(".roll") || ends_with(".pitch") || ends_with(".yaw");
      EXPECT_TRUE(derived || columns.contains(c.name)) << topic << ": " << c.name << " is no field python3-rosbag sees";
    }
  }
  EXPECT_EQ(fields.size(), 7U);
  EXPECT_GT(compared, 1000U);
}

// Bad files: one line naming the file and the problem, never a crash.

TEST(Ros1BagBadInput, TruncatedBagsAndWrongMagic) {
  TempDir dir;
  const std::string good = dir.file("good.bag");
  write_imu_bag(good, rosbag::compression::LZ4);
  const auto size = std::filesystem::file_size(good);
  std::ifstream in(good, std::ios::binary);
  std::vector<char> bytes(size);
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  for (const std::size_t keep : {std::size_t{5}, std::size_t{13}, std::size_t{100}, size / 2, size - 10}) {
    SCOPED_TRACE(keep);
    const std::string cut = dir.file("cut.bag");
    std::ofstream(cut, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(keep));
    const std::string error = load_error(cut);
    EXPECT_EQ(error.rfind(cut + ": ", 0), 0U) << error;
    EXPECT_EQ(error.find('\n'), std::string::npos);
  }
  const std::string fake = dir.file("fake.bag");
  write_text(fake, "this is not a bag\n");
  EXPECT_EQ(load_error(fake), fake + ": not a ROS bag (no '#ROSBAG V2.0' line at the start)");
  const std::string old = dir.file("old.bag");
  write_text(old, "#ROSBAG V1.2\nxxxx");
  EXPECT_EQ(load_error(old), old + ": ROS bag version 1.2; RoverLab reads version 2.0");
}

// A mutant of a small LZ4 bag (written by rosbag::Bag) on which the rosbag
// library itself dies of SIGSEGV: the crash guard's child takes it. One of
// its chunk infos claims 11 781 messages of a chunk that holds 5, so the
// reader goes through the library's View, whose instantiate() crashes (the
// chunk loop read the earlier file of this name, whose byte the library
// misread in the same place, without crashing).
TEST(Ros1BagBadInput, ACrashInsideTheRosbagLibraryIsContained) {
  const std::string path = std::string(ROVERLAB_TEST_DATA) + "/ros/rosbag_segv.bag";
  const std::string error = load_error(path);
  // Under AddressSanitizer the child ends by ASan's report instead of the signal.
  EXPECT_EQ(error.rfind(path + ": corrupt ROS bag: ", 0), 0U) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos);
}

// Chunks whose records lie (read by RoverLab's chunk loop, not the library's
// View): one line naming the chunk and what is wrong with it.
TEST(Ros1BagBadInput, AChunkOfUnknownCompressionOrOfGigabytesIsNamed) {
  TempDir dir;
  const std::string plain = dir.file("plain.bag");
  write_imu_bag(plain, rosbag::compression::Uncompressed, 20);
  std::string bytes = test::read_text(plain);
  const std::size_t none_at = bytes.find("compression=none");  // the first chunk's header
  ASSERT_NE(none_at, std::string::npos);
  bytes.replace(none_at + 12, 4, "zzzz");
  const std::string unknown = dir.file("unknown.bag");
  write_text(unknown, bytes);
  std::string error = load_error(unknown);
  EXPECT_EQ(error.rfind(unknown + ": corrupt ROS bag: the chunk at byte ", 0), 0U) << error;
  EXPECT_NE(error.find(": unknown compression 'zzzz'"), std::string::npos) << error;

  const std::string lz4 = dir.file("lz4.bag");
  write_imu_bag(lz4, rosbag::compression::LZ4, 20);
  bytes = test::read_text(lz4);
  const std::string size_field = std::string("size=", 5);
  // The first chunk's decompressed size: 3 GiB (a uint32 in the record header).
  const std::size_t lz4_at = bytes.find("compression=lz4");
  ASSERT_NE(lz4_at, std::string::npos);
  const std::size_t size_at = bytes.find(size_field, lz4_at);
  ASSERT_NE(size_at, std::string::npos);
  bytes.replace(size_at + size_field.size(), 4, std::string("\x00\x00\x00\xc0", 4));
  const std::string huge = dir.file("huge.bag");
  write_text(huge, bytes);
  error = load_error(huge);
  EXPECT_EQ(error.rfind(huge + ": corrupt ROS bag: the chunk at byte ", 0), 0U) << error;
  EXPECT_NE(error.find(": it claims 3221225472 bytes decompressed, more than RoverLab reads (1 GiB)"),
            std::string::npos)
      << error;
  EXPECT_EQ(error.find('\n'), std::string::npos);
}

std::vector<std::uint8_t> le32(std::uint32_t v) {
  return {static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(v >> 8), static_cast<std::uint8_t>(v >> 16),
          static_cast<std::uint8_t>(v >> 24)};
}

std::string bag_with(const TempDir& dir, const std::string& name, const RawRosMessage& m) {
  const std::string path = dir.file(name);
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  bag.write("/raw", at(0), m);
  bag.close();
  return path;
}

TEST(Ros1BagBadInput, MessagesThatDoNotMatchTheirDefinition) {
  TempDir dir;
  RawRosMessage m;
  m.type = "test_msgs/Pair";
  m.definition = "float64 a\nuint32[] b\n";
  m.bytes = {0, 0, 0, 0, 0, 0, 0xf0, 0x3f};  // a = 1.0, then b's length missing
  std::string path = bag_with(dir, "short.bag", m);
  EXPECT_EQ(load_error(path), path +
                                  ": topic /raw, message 1 (test_msgs/Pair): message of 8 bytes is shorter than its "
                                  "definition (test_msgs/Pair) needs");
  // A 10 GB array: a length field far beyond the message.
  auto huge = le32(0xfffffff0U);
  m.bytes.insert(m.bytes.end(), huge.begin(), huge.end());
  path = bag_with(dir, "huge.bag", m);
  EXPECT_EQ(load_error(path), path +
                                  ": topic /raw, message 1 (test_msgs/Pair): message of 12 bytes is shorter than "
                                  "its definition (test_msgs/Pair) needs");
  // Longer than its definition.
  m.bytes.resize(8);
  auto one = le32(1);
  m.bytes.insert(m.bytes.end(), one.begin(), one.end());
  m.bytes.insert(m.bytes.end(), {7, 0, 0, 0, 9});
  path = bag_with(dir, "long.bag", m);
  EXPECT_EQ(load_error(path), path +
                                  ": topic /raw, message 1 (test_msgs/Pair): message of 17 bytes is longer than its "
                                  "definition (test_msgs/Pair) needs: 1 bytes left over");
  // A definition naming a type it does not define.
  m.definition = "float64 a\nFoo b\n";
  path = bag_with(dir, "unknown.bag", m);
  EXPECT_EQ(load_error(path), path +
                                  ": topic /raw: the definition of test_msgs/Pair: type test_msgs/Pair refers to "
                                  "unknown type test_msgs/Foo");
  m.definition = "float64 a\nPair b\n";
  path = bag_with(dir, "recursive.bag", m);
  EXPECT_EQ(load_error(path),
            path + ": topic /raw: the definition of test_msgs/Pair: type test_msgs/Pair contains itself");
}

// The decoder alone: nested definitions, constants, fixed arrays and the
// well-formed message of a definition written by hand.
TEST(RosMessageDecoder, NestedTypesConstantsAndFixedArrays) {
  const std::string definition =
      "# a comment\n"
      "int8 MODE_A=1  # a constant\n"
      "string LABEL=a=b # another\n"
      "Header header\n"
      "Inner[2] pair\n"
      "bool flag\n"
      "duration d\n"
      "================================================================================\n"
      "MSG: std_msgs/Header\n"
      "uint32 seq\n"
      "time stamp\n"
      "string frame_id\n"
      "================================================================================\n"
      "MSG: pkg/Inner\n"
      "int16 v\n"
      "float32[] f\n";
  io::ros::Decoder decoder(io::ros::parse_definition("pkg/Outer", definition), io::ros::Encoding::ros1);
  std::vector<std::uint8_t> bytes;
  auto put = [&](std::vector<std::uint8_t> b) { bytes.insert(bytes.end(), b.begin(), b.end()); };
  put(le32(7));                               // seq
  put(le32(100));                             // stamp.sec
  put(le32(500'000'000));                     // stamp.nsec
  put(le32(2));                               // frame_id length
  put({'a', 'b'});                            //
  put({0xfe, 0xff});                          // pair[0].v = -2
  put(le32(1));                               // pair[0].f length
  put({0x00, 0x00, 0xc0, 0x3f});              // 1.5f
  put({0x03, 0x00});                          // pair[1].v = 3
  put(le32(0));                               // pair[1].f empty
  put({1});                                   // flag
  put(le32(static_cast<std::uint32_t>(-2)));  // d.sec
  put(le32(250'000'000));                     // d.nsec
  io::ros::DecodedMessage out;
  decoder.decode(bytes.data(), bytes.size(), out);
  const std::vector<std::string> names = decoder.value_names(out);
  const std::vector<std::string> expected = {"header.seq", "header.stamp", "pair.0.v", "pair.0.f.0",
                                             "pair.1.v",   "flag",         "d"};
  EXPECT_EQ(names, expected);
  const std::vector<double> values = {7, 100.5, -2, 1.5, 3, 1, -1.75};
  EXPECT_EQ(out.values, values);
  EXPECT_EQ(out.header_stamp_ns, 100'500'000'000);
}

}  // namespace
