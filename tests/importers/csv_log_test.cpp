#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "core/common/error.h"
#include "importers/csv_log.h"
#include "test_support.h"

using namespace roverlab;
using roverlab::test::TempDir;
using roverlab::test::write_text;

TEST(CsvLog, ReadsHeaderUnitsAndConvertsToSI) {
  TempDir dir;
  write_text(dir.file("bogie.csv"),
             "# bench test, bogie sweep\n"
             "time [ms], bogie [deg], current [A], flag\n"
             "0, 0, 1.5, 1\n"
             "10, 90, , 0\n"
             "20,180,2.5e-1,1\r\n");
  const log::Log lg = io::read_csv_log(dir.file("bogie.csv"));
  ASSERT_EQ(lg.streams().size(), 1u);
  const auto& s = lg.stream("bogie");
  ASSERT_EQ(s.size(), 3u);
  EXPECT_DOUBLE_EQ(s.time()[1], 0.01);
  EXPECT_EQ(s.channel("bogie").unit, "rad");
  EXPECT_NEAR(s.channel("bogie").values[2], M_PI, 1e-15);
  EXPECT_TRUE(std::isnan(s.channel("current").values[1]));  // empty cell: missing sample
  EXPECT_DOUBLE_EQ(s.channel("current").values[2], 0.25);
  EXPECT_EQ(s.channel("flag").unit, "1");
  EXPECT_EQ(lg.metadata.source_file, "bogie.csv");
}

TEST(CsvLog, TimeColumnNeedNotBeFirst) {
  TempDir dir;
  write_text(dir.file("x.csv"), "speed [m/s],t [s]\n1,0\n2,0.5\n");
  const log::Log lg = io::read_csv_log(dir.file("x.csv"));
  const auto& s = lg.stream("x");
  EXPECT_EQ(s.time(), (std::vector<double>{0.0, 0.5}));
  EXPECT_EQ(s.channel("speed").values, (std::vector<double>{1.0, 2.0}));
}

TEST(CsvLog, RoundTripIsBitExact) {
  TempDir dir;
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> t, a, b;
  double now = 1566770959.742861;
  for (int i = 0; i < 2000; ++i) {
    now += 0.004 + 1e-6 * u(rng);
    t.push_back(now);
    a.push_back(u(rng) * std::pow(10.0, static_cast<int>(30 * u(rng))));
    b.push_back(i % 97 == 0 ? std::numeric_limits<double>::quiet_NaN() : u(rng));
  }
  log::Stream s("imu", t);
  s.add_channel("angular_rate_x", "rad/s", a);
  s.add_channel("specific_force_z", "m/s^2", b);
  io::write_csv_stream(s, dir.file("imu.csv"));
  const log::Log lg = io::read_csv_log(dir.file("imu.csv"));
  const auto& back = lg.stream("imu");
  EXPECT_EQ(back.time(), t);
  EXPECT_EQ(back.channel("angular_rate_x").values, a);
  EXPECT_EQ(back.channel("angular_rate_x").unit, "rad/s");
  const auto& bb = back.channel("specific_force_z").values;
  for (std::size_t i = 0; i < b.size(); ++i) {
    if (std::isnan(b[i])) {
      EXPECT_TRUE(std::isnan(bb[i]));
    } else {
      EXPECT_EQ(bb[i], b[i]);
    }
  }
}
