#include "core/comparison/oscillation_test.h"

#include <algorithm>
#include <cmath>
#include <complex>

#include <boost/math/distributions/fisher_f.hpp>
#include <unsupported/Eigen/FFT>

#include "core/common/error.h"

namespace roverlab::comparison {

namespace {

constexpr std::size_t kNeighbours = 16;  // n: 8 bins each side, beyond k +- 1
constexpr std::size_t kFirstBin = 3;     // slower: the block test's

// Welch's averaged periodogram (bins 0 .. segment / 2) of the whole segments
// without NaN, each less its mean and Hann-windowed; `segments` gets M.
std::vector<double> welch_periodogram(const std::vector<double>& x, std::size_t segment, std::size_t& segments) {
  std::vector<double> window(segment), piece(segment), power(segment / 2 + 1, 0.0);
  const double pi = std::acos(-1.0);
  for (std::size_t i = 0; i < segment; ++i)
    window[i] = 0.5 - 0.5 * std::cos(2 * pi * static_cast<double>(i) / static_cast<double>(segment));
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> spectrum;
  segments = 0;
  for (std::size_t start = 0; start + segment <= x.size(); start += segment) {
    const auto first = x.begin() + static_cast<std::ptrdiff_t>(start);
    const auto last = first + static_cast<std::ptrdiff_t>(segment);
    if (!std::all_of(first, last, [](double v) { return std::isfinite(v); })) continue;
    double mean = 0;
    for (auto it = first; it != last; ++it) mean += *it / static_cast<double>(segment);
    for (std::size_t i = 0; i < segment; ++i) piece[i] = (x[start + i] - mean) * window[i];
    fft.fwd(spectrum, piece);
    for (std::size_t k = 0; k < power.size(); ++k) power[k] += std::norm(spectrum[k]);
    ++segments;
  }
  for (double& p : power) p /= static_cast<double>(std::max<std::size_t>(segments, 1));
  return power;
}

// Q_k: the mean of the bins at k +- 2 .. k +- (n / 2 + 1) inside [1, last],
// the window moved inward at the ends so that it always holds n bins.
double neighbour_mean(const std::vector<double>& p, std::size_t k) {
  const std::size_t last = p.size() - 2;  // the Nyquist bin left out
  std::size_t lo = k >= kNeighbours / 2 + 1 ? k - kNeighbours / 2 - 1 : 1;
  std::size_t hi = lo + kNeighbours + 2;  // inclusive, k and k +- 1 among them
  if (hi > last) {
    hi = last;
    lo = hi - kNeighbours - 2;
  }
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t j = lo; j <= hi; ++j) {
    if (j + 1 >= k && j <= k + 1) continue;
    sum += p[j];
    ++n;
  }
  return sum / static_cast<double>(n);
}

// The series whitened for first-order autoregressive noise, w[k] = x[k] - rho x[k-1], with rho the lag-1
// correlation of x less its mean over each `segment` samples, in [0, 0.99]: a smooth noise spectrum becomes flat
// enough for the neighbours to stand for a bin; a line stays a line.
std::vector<double> whitened(const std::vector<double>& x, std::size_t segment, double& rho) {
  double products = 0, squares = 0;
  for (std::size_t start = 0; start + segment <= x.size(); start += segment) {
    double mean = 0;
    for (std::size_t i = start; i < start + segment; ++i) mean += x[i] / static_cast<double>(segment);
    for (std::size_t i = start + 1; i < start + segment; ++i) {
      const double a = x[i - 1] - mean, b = x[i] - mean;
      if (!std::isfinite(a) || !std::isfinite(b)) continue;
      products += a * b;
      squares += a * a;
    }
  }
  rho = squares > 0 ? std::clamp(products / squares, 0.0, 0.99) : 0.0;
  std::vector<double> w(x.size(), NAN);
  for (std::size_t k = 1; k < x.size(); ++k) w[k] = x[k] - rho * x[k - 1];
  return w;
}

}  // namespace

OscillationTest test_oscillation(const std::vector<double>& difference, double alpha, std::size_t segment) {
  if (!(alpha > 0.0 && alpha <= 0.5)) throw DataError("false-alarm rate must be in (0, 0.5]");
  OscillationTest out;
  segment = std::max<std::size_t>(segment, 32);
  while (segment > 32 && difference.size() < 4 * segment) segment /= 2;
  std::size_t segments = 0;
  const std::vector<double> p =
      welch_periodogram(whitened(difference, segment, out.lag_one_correlation), segment, segments);
  const std::size_t last = p.size() - 2;
  if (segments < 4 || last < kFirstBin + kNeighbours + 2) return out;
  out.segments = segments;
  out.bins = last - kFirstBin + 1;
  for (std::size_t k = kFirstBin; k <= last; ++k) {
    const double q = neighbour_mean(p, k);
    const double r = q > 0 ? p[k] / q : 0.0;
    if (r > out.statistic) {
      out.statistic = r;
      out.peak_bin = k;
    }
  }
  out.peak_cycles_per_sample = static_cast<double>(out.peak_bin) / static_cast<double>(segment);
  const auto dof = static_cast<double>(2 * segments);
  const boost::math::fisher_f_distribution<double> f(dof, dof * static_cast<double>(kNeighbours) / 2);
  const double per_bin = alpha / static_cast<double>(out.bins);
  out.threshold = boost::math::quantile(boost::math::complement(f, per_bin));
  out.p_value =
      std::min(1.0, static_cast<double>(out.bins) * boost::math::cdf(boost::math::complement(f, out.statistic)));
  out.differs = out.statistic > out.threshold;
  return out;
}

}  // namespace roverlab::comparison
