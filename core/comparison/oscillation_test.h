#pragma once
// Whether a difference series d = other - base holds a periodic part that
// the block F test (difference_test.h) cannot see because it averages out
// within half a block: a vibration one run has, a scale error on a channel
// that oscillates.
//
// Welch's averaged periodogram of d, whitened first for first-order
// autoregressive noise (w[k] = d[k] - rho d[k-1], rho d's lag-1 correlation
// within segments): M non-overlapping Hann-windowed
// segments, P_k the mean of their |DFT|^2 at frequency bin k. Under noise
// whose spectrum S is smooth over a few bins, P_k ~ S_k chi^2(2M) / 2M, and
// the mean Q_k of the n bins around k (k +- 2..k +- (n/2 + 1): the Hann
// window's leakage keeps a line within k +- 1) ~ S_k chi^2(2M n') / 2M n',
// so R_k = P_k / Q_k ~ F(2M, 2M n'); n' = n / 2 counts the neighbours the
// window correlates in pairs. A line at one frequency lifts its bin over its
// neighbours. T = max_k R_k over the bins tested (from 3 cycles per segment:
// slower parts are the block test's), its threshold the F quantile at
// 1 - alpha / bins (Bonferroni over the bins).

#include <cstddef>
#include <vector>

namespace roverlab::comparison {

struct OscillationTest {
  std::size_t segments = 0;  // M; 0: too short to test (fewer than 4 whole segments)
  std::size_t bins = 0;      // frequency bins tested
  std::size_t peak_bin = 0;  // cycles per segment at the largest R_k
  double peak_cycles_per_sample = 0;
  double lag_one_correlation = 0;  // rho of the whitening w[k] = d[k] - rho d[k-1]
  double statistic = 0;            // T = max_k R_k
  double threshold = 0;            // F(2M, 2M n') quantile at 1 - alpha / bins
  double p_value = 1;              // bins x P(F >= T), at most 1
  bool differs = false;            // T > threshold
};

// The test of `difference` at false-alarm rate `alpha`, with segments of
// `segment` samples (a power of two, at least 32; shorter series: halved down
// to 32). Segments holding a NaN are skipped. Throws DataError when alpha is
// not in (0, 0.5].
OscillationTest test_oscillation(const std::vector<double>& difference, double alpha, std::size_t segment = 256);

}  // namespace roverlab::comparison
