// core/comparison: the difference test's false-alarm rate and power, the
// noise estimate, the cross-correlation offset and the run comparison.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/comparison/compare.h"
#include "core/log/resample.h"

namespace roverlab::comparison {
namespace {

std::vector<double> white(std::mt19937& rng, std::size_t n, double sigma) {
  std::normal_distribution<double> noise(0.0, sigma);
  std::vector<double> x(n);
  for (double& v : x) v = noise(rng);
  return x;
}

// AR(1) noise x[k] = rho x[k-1] + e[k] with unit marginal variance.
std::vector<double> ar1(std::mt19937& rng, std::size_t n, double rho) {
  std::vector<double> x = white(rng, n, std::sqrt(1 - rho * rho));
  for (std::size_t k = 1; k < n; ++k) x[k] += rho * x[k - 1];
  return x;
}

double flagged_fraction(double rho, double bias, std::size_t trials, std::size_t n, double alpha) {
  std::mt19937 rng(7);
  std::size_t flagged = 0;
  for (std::size_t t = 0; t < trials; ++t) {
    std::vector<double> d = rho > 0 ? ar1(rng, n, rho) : white(rng, n, 1.0);
    for (double& v : d) v += bias;
    flagged += test_difference(d, alpha, 20).differs ? 1 : 0;
  }
  return static_cast<double>(flagged) / static_cast<double>(trials);
}

TEST(DifferenceTest, FalseAlarmRateIsAlphaOnWhiteNoise) {
  // 4000 trials at alpha 0.01: 40 expected, binomial sd 6.3.
  const double rate = flagged_fraction(0.0, 0.0, 4000, 2000, 0.01);
  EXPECT_GT(rate, 0.005);
  EXPECT_LT(rate, 0.016);
  EXPECT_NEAR(flagged_fraction(0.0, 0.0, 2000, 2000, 0.05), 0.05, 0.015);
}

TEST(DifferenceTest, FalseAlarmRateHoldsOnAutocorrelatedNoise) {
  // Correlation time ~20 samples, half a block 50: a z test of the mean with
  // the white-noise sigma would flag most of these runs.
  EXPECT_LT(flagged_fraction(0.95, 0.0, 2000, 2000, 0.01), 0.025);
}

TEST(DifferenceTest, FindsABiasOfAFifthOfTheNoiseOverSixThousandSamples) {
  // The mean over 300 samples per block has sd 1/sqrt(300) = 0.058: 0.2 is 3.5 of it.
  EXPECT_GT(flagged_fraction(0.0, 0.2, 200, 6000, 0.01), 0.95);
  EXPECT_LT(flagged_fraction(0.0, 0.02, 200, 6000, 0.01), 0.05);
}

TEST(DifferenceTest, NoNoiseAndNoDifferenceIsNotADifference) {
  EXPECT_FALSE(test_difference(std::vector<double>(100, 0.0), 0.01, 20).differs);
  EXPECT_TRUE(test_difference(std::vector<double>(100, 1e-3), 0.01, 20).differs);
  EXPECT_EQ(test_difference(std::vector<double>(3, 1.0), 0.01, 20).blocks, 0u);
}

TEST(NoiseSigma, SeparatesWhiteNoiseFromASmoothSignal) {
  std::mt19937 rng(3);
  std::vector<double> x = white(rng, 20000, 0.1);
  for (std::size_t k = 0; k < x.size(); ++k) x[k] += 5.0 * std::sin(2 * M_PI * static_cast<double>(k) / 2000.0);
  EXPECT_NEAR(noise_sigma(x), 0.1, 0.005);
}

// A smooth random signal (white noise low-passed twice) sampled at `rate` for `duration` s.
log::Stream smooth_stream(const std::string& name, double rate, double duration, double t_shift, unsigned seed,
                          double noise) {
  std::mt19937 rng(seed);
  const auto n = static_cast<std::size_t>(duration * rate);
  std::vector<double> t(n);
  for (std::size_t k = 0; k < n; ++k) t[k] = t_shift + static_cast<double>(k) / rate;
  log::Stream s(name, t);
  for (const char* channel : {"a", "b"}) {
    std::mt19937 signal_rng(channel[0] == 'a' ? 11 : 12);  // the same signal in every run
    std::vector<double> x = white(signal_rng, n, 1.0);
    for (int pass = 0; pass < 2; ++pass) {
      for (std::size_t k = 1; k < n; ++k) x[k] = 0.98 * x[k - 1] + 0.02 * x[k];
    }
    const std::vector<double> e = white(rng, n, noise);
    for (std::size_t k = 0; k < n; ++k) x[k] += e[k];
    s.add_channel(channel, "m", x);
  }
  return s;
}

TEST(FindTimeOffset, FindsAShiftOfOnePointSevenSecondsWithinOneSample) {
  const double rate = 250;
  const log::Stream base = smooth_stream("imu", rate, 120, 0.0, 1, 0.01);
  const log::Stream other = smooth_stream("imu", rate, 120, 1.7, 2, 0.01);
  double peak = 0;
  const double offset = find_time_offset(base, other, {"a", "b"}, 30, &peak);
  EXPECT_NEAR(offset, 1.7, 1.0 / rate);
  EXPECT_GT(peak, 0.9);
}

log::Log run_with(log::Stream s) {
  log::Log lg;
  lg.add_stream(std::move(s));
  return lg;
}

TEST(CompareRuns, FlagsTheBiasedChannelListsTheMissingOneAndKeepsTheDifference) {
  log::Stream a = smooth_stream("imu", 100, 60, 0.0, 1, 0.05);
  log::Stream b = smooth_stream("imu", 100, 60, 0.5, 2, 0.05);
  std::vector<double> biased = b.channel("b").values;
  for (double& v : biased) v += 0.05;  // one noise sigma: 60 s at 100 Hz shows it
  log::Stream b2("imu", b.time());
  b2.add_channel("a", "m", b.channel("a").values);
  b2.add_channel("b", "m", biased);
  log::Log base = run_with(a);
  log::Stream extra("gps", {0.0, 1.0, 2.0});
  extra.add_channel("east", "m", {0, 1, 2});
  base.add_stream(extra);
  CompareOptions options;
  options.keep_differences = true;
  options.alignment.find_offset = true;
  const RunComparison r = compare_runs(base, run_with(b2), options);
  EXPECT_NEAR(r.alignment.offset_s, 0.5, 0.01);
  ASSERT_EQ(r.channels.size(), 2u);
  EXPECT_FALSE(r.channels[0].differs);
  EXPECT_TRUE(r.channels[1].differs);
  EXPECT_NEAR(r.channels[1].bias, 0.05, 0.005);
  EXPECT_NEAR(r.channels[0].base_sigma, 0.05, 0.005);
  EXPECT_NEAR(r.channels[1].beyond_noise, 0.05, 0.01);
  EXPECT_EQ(r.only_in_base, std::vector<std::string>{"gps/east"});
  // The kept difference is the log model's own interpolation of each run.
  const log::Stream& d = r.differences.stream("difference/imu");
  const std::vector<double>& t = d.time();
  std::vector<double> t_other(t);
  for (double& v : t_other) v += r.alignment.offset_s;
  const std::vector<double> va = a.interpolate("b", t), vb = b2.interpolate("b", t_other);
  for (std::size_t k = 0; k < t.size(); k += 97) EXPECT_NEAR(d.channel("b").values[k], vb[k] - va[k], 1e-12);
}

TEST(CompareRuns, ARunAgainstItselfDiffersNowhereEvenAtARoundingOffset) {
  const log::Log run = run_with(smooth_stream("imu", 100, 60, 0.0, 1, 0.05));
  CompareOptions options;
  options.alignment.offset_s = 1e-15;  // what a parabola through a symmetric peak may give
  const RunComparison r = compare_runs(run, run, options);
  ASSERT_EQ(r.channels.size(), 2u);
  for (const auto& c : r.channels) {
    EXPECT_LT(c.rms, 1e-12);
    EXPECT_FALSE(c.differs) << c.path();
  }
}

// A run along x at `speed` after `wait` s standing, with a sensor reading x.
log::Log driving(double speed, double wait) {
  const std::vector<double> t = log::uniform_times(0, 40, 50);
  std::vector<double> x(t.size()), y(t.size(), 0.0);
  for (std::size_t k = 0; k < t.size(); ++k) x[k] = speed * std::max(0.0, t[k] - wait);
  log::Stream pose("truth/motion", t);
  pose.add_channel("east", "m", x);
  pose.add_channel("north", "m", y);
  log::Log lg;
  lg.add_stream(std::move(pose));
  return lg;
}

TEST(CompareRuns, AlignsByMotionAndByDistance) {
  CompareOptions options;
  options.alignment.by = AlignBy::motion;
  const RunComparison m = compare_runs(driving(0.1, 2.0), driving(0.1, 5.0), options);
  EXPECT_NEAR(m.alignment.offset_s, 3.0, 0.021);
  EXPECT_LT(std::abs(m.channels[0].bias), 0.003);
  options.alignment.by = AlignBy::distance;
  const RunComparison d = compare_runs(driving(0.1, 2.0), driving(0.05, 2.0), options);
  // On the distance axis half the speed reads the same positions.
  EXPECT_LT(d.channels[0].rms, 1e-3);
  options.alignment.by = AlignBy::time;
  EXPECT_GT(compare_runs(driving(0.1, 2.0), driving(0.05, 2.0), options).channels[0].rms, 0.3);
}

}  // namespace
}  // namespace roverlab::comparison

namespace roverlab::comparison {
namespace {

// A sine of `amplitude` (noise sigmas) at `hz` added to white or AR(1) noise sampled at 100 Hz, 60 s.
std::vector<double> noisy_sine(std::mt19937& rng, double rho, double amplitude, double hz) {
  std::vector<double> d = rho > 0 ? ar1(rng, 6000, rho) : white(rng, 6000, 1.0);
  const double pi = std::acos(-1.0);
  for (std::size_t k = 0; k < d.size(); ++k) d[k] += amplitude * std::sin(2 * pi * hz * static_cast<double>(k) / 100);
  return d;
}

// Issue 45: a difference oscillating at a few Hz averages out within every
// half block (0.3 s at 100 Hz and 20 blocks: a 3 Hz sine's whole periods), so
// the block F test misses it; the periodogram test finds it at half the noise,
// at its frequency, and keeps its false-alarm rate on white and on AR(1) noise.
TEST(OscillationTest, FindsAFewHertzSineTheBlockTestMisses) {
  std::mt19937 rng(11);
  std::size_t block_found = 0, found = 0, at_frequency = 0;
  for (int t = 0; t < 100; ++t) {
    const std::vector<double> d = noisy_sine(rng, 0.0, 0.5, 3.0);
    block_found += test_difference(d, 0.005, 20).differs ? 1 : 0;
    const OscillationTest o = test_oscillation(d, 0.005);
    found += o.differs ? 1 : 0;
    at_frequency += std::abs(o.peak_cycles_per_sample * 100 - 3.0) < 0.4 ? 1 : 0;
  }
  EXPECT_LE(block_found, 3u);
  EXPECT_GE(found, 95u);
  EXPECT_GE(at_frequency, 95u);
  for (const double rho : {0.0, 0.9}) {
    std::size_t alarms = 0;
    for (int t = 0; t < 2000; ++t) alarms += test_oscillation(noisy_sine(rng, rho, 0.0, 0.0), 0.01).differs ? 1 : 0;
    EXPECT_LT(alarms, 40u) << "rho " << rho;  // at most 2 %: 1 % nominal
  }
  EXPECT_EQ(test_oscillation(std::vector<double>(100, 0.0), 0.01).segments, 0u);  // too short
}

// compare_runs says the channel differs when the runs differ by the sine alone.
TEST(OscillationTest, CompareRunsFlagsAChannelThatDiffersByAVibration) {
  std::mt19937 rng(5);
  std::vector<double> t(6000);
  for (std::size_t k = 0; k < t.size(); ++k) t[k] = static_cast<double>(k) / 100;
  log::Log a, b;
  log::Stream sa("imu", t), sb("imu", t);
  sa.add_channel("x", "m/s^2", white(rng, t.size(), 0.1), "");
  std::vector<double> shaken = white(rng, t.size(), 0.1);
  for (std::size_t k = 0; k < t.size(); ++k) shaken[k] += 0.07 * std::sin(2 * std::acos(-1.0) * 4.0 * t[k]);
  sb.add_channel("x", "m/s^2", shaken, "");
  a.add_stream(std::move(sa));
  b.add_stream(std::move(sb));
  const RunComparison r = compare_runs(a, b, CompareOptions{});
  ASSERT_EQ(r.channels.size(), 1u);
  EXPECT_FALSE(r.channels[0].test.differs);
  EXPECT_TRUE(r.channels[0].oscillation.differs);
  EXPECT_TRUE(r.channels[0].differs);
}

}  // namespace
}  // namespace roverlab::comparison
