#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include <vtkDoubleArray.h>

#include "core/log/resample.h"
#include "views/display_series.h"

using namespace roverlab;

TEST(DisplaySeries, TenMillionSamplesKeepTheirExtremesAndSpikes) {
  const std::size_t n = 10'000'000;
  std::vector<double> t(n), v(n);
  for (std::size_t i = 0; i < n; ++i) {
    t[i] = 1e-4 * static_cast<double>(i);
    v[i] = std::sin(t[i]);
  }
  v[1234567] = 50.0;   // a one-sample spike
  v[7654321] = -40.0;  // and a dip
  const auto d = views::decimate_min_max(t, v, t.front(), t.back(), 1000);
  EXPECT_LE(d.time.size(), 2000u);
  EXPECT_GE(d.time.size(), 1000u);
  EXPECT_EQ(*std::max_element(d.value.begin(), d.value.end()), 50.0);
  EXPECT_EQ(*std::min_element(d.value.begin(), d.value.end()), -40.0);
  EXPECT_TRUE(std::is_sorted(d.time.begin(), d.time.end()));
  // Every point shown is a real sample.
  for (std::size_t k = 0; k < d.time.size(); k += 97) {
    const auto i = static_cast<std::size_t>(std::llround(d.time[k] / 1e-4));
    EXPECT_EQ(v[i], d.value[k]);
  }
}

TEST(DisplaySeries, WindowAndSmallInputsAreExact) {
  std::vector<double> t{0, 1, 2, 3, 4, 5}, v{0, 10, std::nan(""), 30, 40, 50};
  const auto all = views::decimate_min_max(t, v, 0.0, 5.0, 10);
  EXPECT_EQ(all.time, (std::vector<double>{0, 1, 3, 4, 5}));  // NaN skipped
  const auto window = views::decimate_min_max(t, v, 2.5, 4.5, 10);
  EXPECT_EQ(window.value, (std::vector<double>{30, 40}));
  EXPECT_TRUE(views::decimate_min_max(t, v, 6.0, 7.0, 10).time.empty());
}

TEST(DisplaySeries, VtkTableForCharts) {
  log::Stream s("imu", log::uniform_times(0.0, 99.9, 10.0));
  std::vector<double> ramp(s.size());
  for (std::size_t i = 0; i < ramp.size(); ++i) ramp[i] = static_cast<double>(i);
  s.add_channel("angular_rate_z", "rad/s", ramp);
  const auto table = views::make_display_table(s, "angular_rate_z", 0.0, 100.0, 100);
  ASSERT_EQ(table->GetNumberOfColumns(), 2);
  EXPECT_STREQ(table->GetColumn(1)->GetName(), "angular_rate_z");
  EXPECT_EQ(table->GetNumberOfRows(), 200);
  auto* values = vtkDoubleArray::SafeDownCast(table->GetColumn(1));
  ASSERT_NE(values, nullptr);
  EXPECT_EQ(values->GetValue(0), 0.0);
  EXPECT_EQ(values->GetValue(199), 999.0);
  EXPECT_THROW(views::make_display_table(s, "missing", 0.0, 1.0, 10), std::runtime_error);
}
