#include "core/terramechanics/traction_surface.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "core/common/error.h"

namespace roverlab::terramechanics {

PolynomialSurface::PolynomialSurface(int order, std::vector<double> coefficients)
    : order_(order), coefficients_(std::move(coefficients)) {
  if (order < 0 || order > 6) throw DataError("polynomial order must be 0..6");
  if (coefficients_.size() != term_count(order)) {
    throw DataError("polynomial of order " + std::to_string(order) + " needs " + std::to_string(term_count(order)) +
                    " coefficients");
  }
}

std::pair<int, int> PolynomialSurface::exponents(std::size_t i) {
  int degree = 0;
  std::size_t first = 0;
  while (first + static_cast<std::size_t>(degree + 1) <= i) {
    first += static_cast<std::size_t>(degree + 1);
    ++degree;
  }
  const int l = static_cast<int>(i - first);  // Eq. 2.28: within a degree, W's power rises
  return {degree - l, l};
}

double PolynomialSurface::operator()(double load, double slip) const {
  double slip_power[7], load_power[7];  // order <= 6
  slip_power[0] = load_power[0] = 1.0;
  for (int k = 1; k <= order_; ++k) {
    slip_power[k] = slip_power[k - 1] * slip;
    load_power[k] = load_power[k - 1] * load;
  }
  double sum = 0.0;
  std::size_t i = 0;
  for (int degree = 0; degree <= order_; ++degree) {
    for (int l = 0; l <= degree; ++l, ++i) sum += coefficients_[i] * slip_power[degree - l] * load_power[l];
  }
  return sum;
}

FitError fit_error(const PolynomialSurface& p, const std::vector<SurfaceSample>& samples) {
  FitError e;
  if (samples.empty()) return e;
  for (const auto& s : samples) {
    const double d = std::abs(p(s.load, s.slip) - s.value);
    e.mean_abs += d;
    e.rmse += d * d;
    e.max_abs = std::max(e.max_abs, d);
  }
  e.mean_abs /= static_cast<double>(samples.size());
  e.rmse = std::sqrt(e.rmse / static_cast<double>(samples.size()));
  return e;
}

PolynomialSurface fit_surface(const std::vector<SurfaceSample>& samples, int order) {
  if (order < 1 || order > 6) throw DataError("polynomial order must be 1..6");
  const std::size_t terms = PolynomialSurface::term_count(order);
  if (samples.size() < terms) {
    throw DataError("order " + std::to_string(order) + " needs at least " + std::to_string(terms) + " points, got " +
                    std::to_string(samples.size()));
  }
  // Monomials in raw units (so the coefficients read as Eq. 2.28), columns
  // equilibrated before a column-pivoting QR for conditioning.
  Eigen::MatrixXd a(samples.size(), terms);
  Eigen::VectorXd y(samples.size());
  for (std::size_t r = 0; r < samples.size(); ++r) {
    const double w = std::sqrt(std::max(samples[r].weight, 0.0));
    for (std::size_t i = 0; i < terms; ++i) {
      const auto [k, l] = PolynomialSurface::exponents(i);
      a(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(i)) =
          w * std::pow(samples[r].slip, k) * std::pow(samples[r].load, l);
    }
    y(static_cast<Eigen::Index>(r)) = w * samples[r].value;
  }
  Eigen::VectorXd scale = a.colwise().norm().transpose();
  for (Eigen::Index i = 0; i < scale.size(); ++i) {
    if (scale(i) == 0.0) scale(i) = 1.0;
  }
  const Eigen::MatrixXd scaled = a * scale.cwiseInverse().asDiagonal();
  const Eigen::VectorXd x = scaled.colPivHouseholderQr().solve(y).cwiseQuotient(scale);
  return PolynomialSurface(order, std::vector<double>(x.data(), x.data() + x.size()));
}

SurfaceFit fit_surface_cross_validated(const std::vector<SurfaceSample>& samples, int max_order, int folds,
                                       unsigned seed) {
  if (samples.size() < 6) throw DataError("cross-validation needs at least 6 points");
  folds = std::max(2, std::min<int>(folds, static_cast<int>(samples.size())));
  std::vector<std::size_t> order_of(samples.size());
  std::iota(order_of.begin(), order_of.end(), 0);
  std::mt19937 rng(seed);
  std::shuffle(order_of.begin(), order_of.end(), rng);
  SurfaceFit best;
  double best_cv = INFINITY;
  for (int order = 1; order <= max_order; ++order) {
    // Each fold's training set must still determine the polynomial.
    const std::size_t terms = PolynomialSurface::term_count(order);
    const std::size_t smallest_train = samples.size() - (samples.size() + folds - 1) / folds;
    if (smallest_train < terms) break;
    double sq = 0.0, wsum = 0.0;
    for (int f = 0; f < folds; ++f) {
      std::vector<SurfaceSample> train, test;
      for (std::size_t i = 0; i < order_of.size(); ++i) {
        (static_cast<int>(i % folds) == f ? test : train).push_back(samples[order_of[i]]);
      }
      const PolynomialSurface p = fit_surface(train, order);
      for (const auto& s : test) {
        const double d = p(s.load, s.slip) - s.value;
        sq += s.weight * d * d;
        wsum += s.weight;
      }
    }
    OrderScore score;
    score.order = order;
    score.cv_rmse = std::sqrt(sq / std::max(wsum, 1e-300));
    const PolynomialSurface full = fit_surface(samples, order);
    score.train_rmse = fit_error(full, samples).rmse;
    best.orders.push_back(score);
    if (score.cv_rmse < best_cv) best_cv = score.cv_rmse;
  }
  if (best.orders.empty()) throw DataError("too few points for a polynomial surface");
  int chosen = best.orders.back().order;
  for (const auto& s : best.orders) {
    if (s.cv_rmse <= 1.02 * best_cv) {
      chosen = s.order;
      break;
    }
  }
  best.surface = fit_surface(samples, chosen);
  best.error = fit_error(best.surface, samples);
  return best;
}

OccupancyGrid OccupancyGrid::build(const std::vector<SurfaceSample>& samples, double load_min, double load_max,
                                   double slip_min, double slip_max, int load_bins, int slip_bins) {
  if (!(load_max > load_min) || !(slip_max > slip_min) || load_bins < 1 || slip_bins < 1) {
    throw DataError("occupancy grid needs non-empty ranges and at least one bin");
  }
  OccupancyGrid g{load_min,
                  load_max,
                  slip_min,
                  slip_max,
                  load_bins,
                  slip_bins,
                  std::vector<int>(static_cast<std::size_t>(load_bins * slip_bins), 0)};
  for (const auto& s : samples) {
    const int l = static_cast<int>(std::floor((s.load - load_min) / (load_max - load_min) * load_bins));
    const int k = static_cast<int>(std::floor((s.slip - slip_min) / (slip_max - slip_min) * slip_bins));
    if (l < 0 || k < 0 || l > load_bins || k > slip_bins) continue;
    ++g.counts[static_cast<std::size_t>(std::min(l, load_bins - 1) * slip_bins + std::min(k, slip_bins - 1))];
  }
  return g;
}

double OccupancyGrid::coverage() const {
  const auto filled = std::count_if(counts.begin(), counts.end(), [](int c) { return c > 0; });
  return static_cast<double>(filled) / static_cast<double>(counts.size());
}

bool OccupancyGrid::covered(double load, double slip) const {
  const int l = static_cast<int>(std::floor((load - load_min) / (load_max - load_min) * load_bins));
  const int k = static_cast<int>(std::floor((slip - slip_min) / (slip_max - slip_min) * slip_bins));
  if (l < 0 || k < 0 || l > load_bins || k > slip_bins) return false;
  return count(std::min(l, load_bins - 1), std::min(k, slip_bins - 1)) > 0;
}

}  // namespace roverlab::terramechanics
