#pragma once
// What tests/importers/ros1_bag_test.cpp (the ROS library's writer) and
// tests/data/mcap/make_kapvik_mcap.mjs (the MCAP project's writer) record, and
// what resources/mappings/ros_kapvik.json makes of it: a planar rocker-bogie's
// IMU, joints, commands, velocimeter (TwistStamped), three wheel wrenches
// (WrenchStamped) and its pose on /tf (TFMessage). Message i is recorded at
// 0.05 i s; value(i, k) = 0.1 i + 1e-7 k - 3.3 (the same IEEE operations in
// C++ and JavaScript). On /tf, message i carries base_link and mast (mast
// first when i is odd), or mast alone when i % 4 == 3.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "core/log/log.h"

namespace roverlab::test::kapvik {

constexpr int kMessages = 40;

inline double value(int i, int k) { return 0.1 * i + 1e-7 * k - 3.3; }
inline bool has_base_link(int i) { return i % 4 != 3; }
inline double pitch(int i) { return 0.01 * i; }  // base_link's rotation (0, sin(p/2), 0, cos(p/2))

// Every mapped value equal to what was written (bit for bit; the pitch, which
// goes through sin and atan2, to 1e-12), in SI units.
inline void expect_mapped_log(const log::Log& lg) {
  const std::string wheels[3] = {"1", "2", "3"};
  const log::Stream& imu = lg.stream("imu");
  const log::Stream& joints = lg.stream("joints");
  const log::Stream& commands = lg.stream("commands");
  const log::Stream& velocimeter = lg.stream("velocimeter");
  const log::Stream& forces = lg.stream("forces");
  ASSERT_EQ(imu.size(), static_cast<std::size_t>(kMessages));
  ASSERT_EQ(forces.size(), static_cast<std::size_t>(kMessages));
  ASSERT_EQ(velocimeter.size(), static_cast<std::size_t>(kMessages));
  EXPECT_EQ(forces.channel("load_1").unit, "N");
  EXPECT_EQ(forces.channel("axle_torque_3").unit, "N*m");
  EXPECT_EQ(velocimeter.channel("forward_speed").unit, "m/s");
  EXPECT_EQ(commands.channel("wheel_torque_2").unit, "N*m");
  for (int i = 0; i < kMessages; ++i) {
    EXPECT_NEAR(imu.time()[i], 0.05 * i, 1e-9);
    EXPECT_EQ(forces.time()[i], imu.time()[i]);
    EXPECT_EQ(imu.channel("specific_force_x").values[i], value(i, 0));
    EXPECT_EQ(imu.channel("specific_force_z").values[i], value(i, 2));
    EXPECT_EQ(imu.channel("pitch_rate").values[i], value(i, 4));
    EXPECT_EQ(joints.channel("wheel_angle_1").values[i], value(i, 10));
    EXPECT_EQ(joints.channel("bogie_angle").values[i], value(i, 11));
    EXPECT_EQ(joints.channel("wheel_angle_3").values[i], value(i, 13));
    EXPECT_EQ(commands.channel("wheel_torque_1").values[i], value(i, 20));
    EXPECT_EQ(commands.channel("wheel_torque_3").values[i], value(i, 22));
    EXPECT_EQ(velocimeter.channel("forward_speed").values[i], value(i, 30));
    EXPECT_EQ(velocimeter.channel("pitch_rate").values[i], value(i, 31));
    for (int w = 0; w < 3; ++w) {
      EXPECT_EQ(forces.channel("perpendicular_" + wheels[w]).values[i], value(i, 40 + w));
      EXPECT_EQ(forces.channel("load_" + wheels[w]).values[i], value(i, 50 + w));
      EXPECT_EQ(forces.channel("axle_torque_" + wheels[w]).values[i], value(i, 60 + w));
    }
  }
  // The pose: base_link's transform wherever it is in the message, and no
  // sample from the messages that carry mast alone.
  const log::Stream& pose = lg.stream("pose");
  ASSERT_EQ(pose.size(), static_cast<std::size_t>(kMessages - kMessages / 4));
  EXPECT_EQ(pose.channel("x").unit, "m");
  EXPECT_EQ(pose.channel("pitch").unit, "rad");
  std::size_t row = 0;
  for (int i = 0; i < kMessages; ++i) {
    if (!has_base_link(i)) continue;
    EXPECT_NEAR(pose.time()[row], 0.05 * i, 1e-9);
    EXPECT_EQ(pose.channel("x").values[row], value(i, 70));
    EXPECT_EQ(pose.channel("y").values[row], value(i, 71));
    EXPECT_EQ(pose.channel("z").values[row], value(i, 72));
    EXPECT_NEAR(pose.channel("pitch").values[row], pitch(i), 1e-12);
    EXPECT_EQ(pose.channel("roll").values[row], 0.0);
    ++row;
  }
}

}  // namespace roverlab::test::kapvik
