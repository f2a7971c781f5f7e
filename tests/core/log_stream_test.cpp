#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/common/error.h"
#include "core/log/log.h"
#include "core/log/stream.h"

using roverlab::DataError;
using namespace roverlab::log;

namespace {

Stream ramp_stream() {
  // t = 0, 0.5, 1.0, 2.0 ; v = 10 * t
  Stream s("imu", {0.0, 0.5, 1.0, 2.0});
  s.add_channel("speed", "m/s", {0.0, 5.0, 10.0, 20.0}, "ramp");
  return s;
}

}  // namespace

TEST(Stream, RejectsNonFiniteAndNonIncreasingTime) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(Stream("a", {0.0, nan, 2.0}), DataError);
  EXPECT_THROW(Stream("a", {0.0, 1.0, inf}), DataError);
  EXPECT_THROW(Stream("a", {0.0, 1.0, 1.0}), DataError);
  EXPECT_THROW(Stream("a", {0.0, 2.0, 1.0}), DataError);
  EXPECT_NO_THROW(Stream("a", {-1.0, 0.0, 1e-9}));
  EXPECT_NO_THROW(Stream("a", {}));
  try {
    Stream("imu", {0.0, 2.0, 1.0});
    FAIL();
  } catch (const DataError& e) {
    EXPECT_NE(std::string(e.what()).find("sample 2"), std::string::npos) << e.what();
  }
}

TEST(Stream, ValidatesNames) {
  EXPECT_THROW(Stream("", {}), DataError);
  EXPECT_THROW(Stream("/imu", {}), DataError);
  EXPECT_THROW(Stream("truth//imu", {}), DataError);
  EXPECT_NO_THROW(Stream("truth/imu", {}));
  EXPECT_NO_THROW(Stream("estimate/ekf/contact", {}));
  Stream s("imu", {0.0, 1.0});
  EXPECT_THROW(s.add_channel("a/b", "1", {1, 2}), DataError);
  EXPECT_THROW(s.add_channel("", "1", {1, 2}), DataError);
}

TEST(Stream, ChannelMustMatchTimeBaseAndBeSI) {
  Stream s("imu", {0.0, 1.0, 2.0});
  EXPECT_THROW(s.add_channel("x", "m", {1.0, 2.0}), DataError);
  EXPECT_THROW(s.add_channel("x", "furlong", {1.0, 2.0, 3.0}), DataError);
  EXPECT_THROW(s.add_channel("x", "deg", {1.0, 2.0, 3.0}), DataError);  // not SI
  s.add_channel("x", "rad", {1.0, 2.0, 3.0});
  EXPECT_THROW(s.add_channel("x", "rad", {1.0, 2.0, 3.0}), DataError);  // duplicate
  EXPECT_EQ(s.channel("x").values[2], 3.0);
  EXPECT_THROW(s.channel("y"), DataError);
  EXPECT_EQ(s.find_channel("y"), nullptr);
}

TEST(Stream, TimeToIndexByBinarySearch) {
  const Stream s = ramp_stream();
  EXPECT_EQ(s.index_at_or_before(-0.1), Stream::npos);
  EXPECT_EQ(s.index_at_or_before(0.0), 0u);
  EXPECT_EQ(s.index_at_or_before(0.49), 0u);
  EXPECT_EQ(s.index_at_or_before(0.5), 1u);
  EXPECT_EQ(s.index_at_or_before(1.99), 2u);
  EXPECT_EQ(s.index_at_or_before(100.0), 3u);
  EXPECT_EQ(s.nearest_index(0.7), 1u);
  EXPECT_EQ(s.nearest_index(0.8), 2u);
  EXPECT_EQ(s.nearest_index(-5.0), 0u);
  EXPECT_EQ(s.nearest_index(9.0), 3u);
  EXPECT_EQ(s.index_at_or_before(std::nan("")), Stream::npos);
}

TEST(Stream, LinearInterpolationAndNoExtrapolation) {
  const Stream s = ramp_stream();
  EXPECT_DOUBLE_EQ(s.value_at("speed", 0.25), 2.5);
  EXPECT_DOUBLE_EQ(s.value_at("speed", 1.5), 15.0);
  EXPECT_DOUBLE_EQ(s.value_at("speed", 2.0), 20.0);
  EXPECT_DOUBLE_EQ(s.value_at("speed", 0.0), 0.0);
  EXPECT_TRUE(std::isnan(s.value_at("speed", -0.01)));
  EXPECT_TRUE(std::isnan(s.value_at("speed", 2.01)));
  const auto v = s.interpolate("speed", {1.75, 0.1, 3.0});
  EXPECT_DOUBLE_EQ(v[0], 17.5);
  EXPECT_DOUBLE_EQ(v[1], 1.0);
  EXPECT_TRUE(std::isnan(v[2]));
}

TEST(Stream, RatesAndDurations) {
  Stream s("imu", {10.0, 10.004, 10.008, 10.012, 10.016});
  EXPECT_NEAR(s.duration(), 0.016, 1e-12);
  EXPECT_NEAR(s.mean_rate_hz(), 250.0, 1e-6);
  EXPECT_EQ(Stream("e", {}).mean_rate_hz(), 0.0);
  EXPECT_TRUE(std::isnan(Stream("e", {}).start_time()));
}

TEST(Stream, SliceKeepsSamplesInWindow) {
  const Stream s = ramp_stream();
  const Stream part = s.slice(0.5, 1.5);
  ASSERT_EQ(part.size(), 2u);
  EXPECT_EQ(part.time()[0], 0.5);
  EXPECT_EQ(part.channel("speed").values[1], 10.0);
  EXPECT_EQ(part.channel("speed").unit, "m/s");
  EXPECT_EQ(s.slice(3.0, 4.0).size(), 0u);
  EXPECT_EQ(s.slice(1.5, 0.5).size(), 0u);
  EXPECT_THROW(s.slice(std::nan(""), 1.0), DataError);
}

TEST(Log, LookupByNameAndPath) {
  Log lg;
  lg.metadata.rover_id = "exomars_bb2";
  lg.add_stream(ramp_stream());
  Stream truth("truth/imu", {0.0, 1.0});
  truth.add_channel("pitch", "rad", {0.1, 0.2});
  lg.add_stream(std::move(truth));
  EXPECT_THROW(lg.add_stream(Stream("imu", {})), DataError);
  EXPECT_EQ(lg.channel("imu/speed").values[3], 20.0);
  EXPECT_EQ(lg.channel("truth/imu/pitch").values[1], 0.2);
  EXPECT_THROW(lg.channel("truth/imu/roll"), DataError);
  EXPECT_THROW(lg.channel("speed"), DataError);
  EXPECT_THROW(lg.stream("gps"), DataError);
  EXPECT_EQ(lg.total_samples(), 4u * 2 + 2u * 2);
  const Log part = lg.slice(0.9, 1.1);
  EXPECT_EQ(part.metadata.rover_id, "exomars_bb2");
  EXPECT_EQ(part.stream("imu").size(), 1u);
  EXPECT_EQ(part.stream("truth/imu").size(), 1u);
}
