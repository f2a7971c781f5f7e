#pragma once
// Whether a difference series d = other - base holds more than noise, and
// how large the noise of one stream is.
//
// The test splits d into K blocks and each block into halves with means h1
// and h2. Under "no difference" (zero-mean noise whose correlation time is
// short against half a block) the block means m = (h1 + h2) / 2 and the
// half-differences e = (h1 - h2) / 2 are independent with one variance, so
// T = mean(m^2) / mean(e^2) follows Fisher's F(K, K): the noise scale comes
// from the data at the block's own time scale, autocorrelation included,
// and the false-alarm rate of "T above the 1 - alpha quantile" is alpha.
// A bias or a drift moves the block means and not the half-differences.
// Noise correlated over a good part of a half block correlates h1 and h2;
// T is corrected for it as for first-order autoregressive noise, with the
// lag-1 correlation measured within the halves.

#include <cstddef>
#include <vector>

namespace roverlab::comparison {

struct DifferenceTest {
  std::size_t blocks = 0;          // blocks used (each with two finite halves); 0: too short to test
  double statistic = 0;            // T = mean(m^2) / mean(e^2)
  double threshold = 0;            // F(blocks, blocks) quantile at 1 - alpha
  double p_value = 1;              // P(F >= T) under no difference
  double lag_one_correlation = 0;  // of the noise, its AR(1) correction applied to T
  bool differs = false;            // T > threshold
};

// The block F test of `difference` (NaN samples skipped) at false-alarm rate
// `alpha` with `blocks` blocks (fewer when the series is short: at least 4
// samples a block). Throws DataError when alpha is not in (0, 0.5].
DifferenceTest test_difference(const std::vector<double>& difference, double alpha, std::size_t blocks);

// White-noise sigma of a series from its second differences, which remove a
// smooth signal: var(x[k+1] - 2 x[k] + x[k-1]) = 6 sigma^2 for white noise.
// Robust (1.4826 x median absolute deviation), from at most 65536 evenly
// spread second differences; their RMS when the MAD is 0 (quantised data).
// NaN when fewer than 3 finite consecutive samples.
double noise_sigma(const std::vector<double>& values);

}  // namespace roverlab::comparison
