#include "core/comparison/difference_test.h"

#include <algorithm>
#include <cmath>

#include <boost/math/distributions/fisher_f.hpp>

#include "core/common/error.h"

namespace roverlab::comparison {

namespace {

// Mean of the finite values in [begin, end); NaN when fewer than two.
double finite_mean(const std::vector<double>& x, std::size_t begin, std::size_t end) {
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t k = begin; k < end; ++k) {
    if (std::isfinite(x[k])) {
      sum += x[k];
      ++n;
    }
  }
  return n >= 2 ? sum / static_cast<double>(n) : NAN;
}

double median_of(std::vector<double>& v) {
  const auto middle = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), middle, v.end());
  return *middle;
}

// The lag-1 autocorrelation of the noise, from the samples of each half
// block less the half's mean (a bias or a slow drift does not enter it).
struct LagOneSums {
  double products = 0, squares = 0;
  void add(const std::vector<double>& x, std::size_t begin, std::size_t end, double mean) {
    for (std::size_t k = begin; k + 1 < end; ++k) {
      const double a = x[k] - mean, b = x[k + 1] - mean;
      if (!std::isfinite(a)) continue;
      squares += a * a;
      if (std::isfinite(b)) products += a * b;
    }
  }
  // Corrected for the bias of a mean removed over `length` samples, about
  // -(1 + 3 rho) / length (Marriott and Pope 1954); in [0, 0.99].
  double correlation(double length) const {
    if (!(squares > 0)) return 0.0;
    const double r = products / squares;
    return std::clamp(r + (1 + 3 * r) / length, 0.0, 0.99);
  }
};

// Under AR(1) noise of lag-1 correlation rho, adjacent half-block means of L
// samples each have variance V and covariance C (unit noise variance); the
// block mean m then has variance (V + C) / 2 and the half-difference e
// (V - C) / 2, so mean(m^2) / mean(e^2) is scaled by (V - C) / (V + C) back to F.
double autoregressive_factor(double rho, double length) {
  if (rho <= 0) return 1.0;
  const auto n = static_cast<std::size_t>(std::max(1.0, std::round(length)));
  double v = static_cast<double>(n), power = 1.0;
  for (std::size_t k = 1; k < n; ++k) {
    power *= rho;
    v += 2.0 * static_cast<double>(n - k) * power;
  }
  const double c = rho * std::pow(1 - std::pow(rho, static_cast<double>(n)), 2) / ((1 - rho) * (1 - rho));
  return (v - c) / (v + c);
}

}  // namespace

DifferenceTest test_difference(const std::vector<double>& difference, double alpha, std::size_t blocks) {
  if (!(alpha > 0.0 && alpha <= 0.5)) throw DataError("false-alarm rate must be in (0, 0.5]");
  DifferenceTest out;
  const std::size_t n = difference.size();
  const std::size_t k_max = std::min(blocks, n / 4);
  double sum_m = 0, sum_e = 0;
  LagOneSums lag_one;
  for (std::size_t j = 0; j < k_max; ++j) {
    const std::size_t begin = j * n / k_max, end = (j + 1) * n / k_max, middle = (begin + end) / 2;
    const double h1 = finite_mean(difference, begin, middle), h2 = finite_mean(difference, middle, end);
    if (std::isnan(h1) || std::isnan(h2)) continue;
    sum_m += 0.25 * (h1 + h2) * (h1 + h2);
    sum_e += 0.25 * (h1 - h2) * (h1 - h2);
    lag_one.add(difference, begin, middle, h1);
    lag_one.add(difference, middle, end, h2);
    ++out.blocks;
  }
  if (out.blocks < 2) return out;
  const auto dof = static_cast<double>(out.blocks);
  const boost::math::fisher_f_distribution<double> f(dof, dof);
  out.threshold = boost::math::quantile(boost::math::complement(f, alpha));
  const double half = 0.5 * static_cast<double>(n) / static_cast<double>(k_max);
  out.lag_one_correlation = lag_one.correlation(half);
  if (sum_e > 0) {
    out.statistic = sum_m / sum_e * autoregressive_factor(out.lag_one_correlation, half);
    out.p_value = boost::math::cdf(boost::math::complement(f, out.statistic));
  } else {
    // No noise at all: any systematic difference is one.
    out.statistic = sum_m > 0 ? INFINITY : 0.0;
    out.p_value = sum_m > 0 ? 0.0 : 1.0;
  }
  out.differs = out.statistic > out.threshold;
  return out;
}

double noise_sigma(const std::vector<double>& values) {
  const std::size_t n = values.size();
  if (n < 3) return NAN;
  const std::size_t stride = std::max<std::size_t>(1, (n - 2) / 65536);
  std::vector<double> second;
  second.reserve((n - 2) / stride + 1);
  for (std::size_t k = 1; k + 1 < n; k += stride) {
    const double d2 = values[k + 1] - 2.0 * values[k] + values[k - 1];
    if (std::isfinite(d2)) second.push_back(d2);
  }
  if (second.empty()) return NAN;
  const double centre = median_of(second);
  double sum_squares = 0;
  for (double& v : second) {
    sum_squares += v * v;
    v = std::abs(v - centre);
  }
  const double mad = median_of(second);
  const double spread = mad > 0 ? 1.4826 * mad : std::sqrt(sum_squares / static_cast<double>(second.size()));
  return spread / std::sqrt(6.0);
}

}  // namespace roverlab::comparison
