#include <gtest/gtest.h>

#include <cmath>

#include "core/common/error.h"
#include "core/log/resample.h"

using namespace roverlab::log;

TEST(Resample, UniformTimes) {
  const auto t = uniform_times(1.0, 2.0, 10.0);
  ASSERT_EQ(t.size(), 11u);
  EXPECT_DOUBLE_EQ(t.back(), 2.0);
  EXPECT_THROW(uniform_times(0.0, 1.0, 0.0), roverlab::DataError);
  EXPECT_THROW(uniform_times(1.0, 0.0, 1.0), roverlab::DataError);
}

TEST(Resample, InterpolatesEveryChannel) {
  Stream s("wheels", {0.0, 1.0, 2.0});
  s.add_channel("angle", "rad", {0.0, 2.0, 6.0});
  s.add_channel("current", "A", {1.0, 1.0, 3.0});
  const Stream r = resample(s, {0.5, 1.5, 2.5}, "wheels_resampled");
  EXPECT_EQ(r.name(), "wheels_resampled");
  EXPECT_DOUBLE_EQ(r.channel("angle").values[0], 1.0);
  EXPECT_DOUBLE_EQ(r.channel("angle").values[1], 4.0);
  EXPECT_TRUE(std::isnan(r.channel("angle").values[2]));
  EXPECT_DOUBLE_EQ(r.channel("current").values[1], 2.0);
  EXPECT_EQ(r.channel("current").unit, "A");
}

TEST(Resample, AlignPutsTwoStreamsOnOneTimeBase) {
  // imu at 4 Hz from 0 to 3 s, wheels at 1 Hz from 1 to 4 s.
  Stream imu("imu", uniform_times(0.0, 3.0, 4.0));
  std::vector<double> rate;
  for (double t : imu.time()) rate.push_back(2.0 * t);
  imu.add_channel("angular_rate_z", "rad/s", rate);
  imu.add_channel("angle", "rad", std::vector<double>(imu.size(), 7.0));
  Stream wheels("wheels", {1.0, 2.0, 3.0, 4.0});
  wheels.add_channel("angle", "rad", {10.0, 20.0, 30.0, 40.0});

  const Stream a = align(imu, wheels, "imu+wheels");
  ASSERT_EQ(a.size(), 9u);  // 1.0, 1.25, ..., 3.0
  EXPECT_DOUBLE_EQ(a.start_time(), 1.0);
  EXPECT_DOUBLE_EQ(a.end_time(), 3.0);
  EXPECT_DOUBLE_EQ(a.channel("angular_rate_z").values[0], 2.0);
  EXPECT_DOUBLE_EQ(a.channel("angle").values[0], 7.0);          // base keeps its name
  EXPECT_DOUBLE_EQ(a.channel("wheels.angle").values[1], 12.5);  // other is prefixed
  EXPECT_DOUBLE_EQ(a.channel("wheels.angle").values[8], 30.0);

  Stream late("late", {10.0, 11.0});
  EXPECT_THROW(align(imu, late, "x"), roverlab::DataError);
}
