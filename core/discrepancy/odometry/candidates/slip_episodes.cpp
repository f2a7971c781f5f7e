#include <algorithm>
#include <cmath>

#include "core/discrepancy/odometry/candidates.h"

namespace roverlab::analysis {

namespace {

// Slip episodes: one slip value per window of the fit part; the test part
// can only use their median (episodes are not predictable).
class SlipEpisodes final : public OdometryCandidateModel {
 public:
  explicit SlipEpisodes(const OdometryCandidateContext& c)
      : fit_wheels_(c.fit_wheels), test_n_(c.test_wheel_samples), window_(c.options.slip_window) {
    const double fit_span = fit_wheels_.time.back() - fit_wheels_.time.front();
    windows_ = std::max(1, static_cast<int>(std::ceil(fit_span / window_)));
  }
  std::string name() const override { return "slip episodes"; }
  std::string cause() const override { return "the wheels slip by different amounts over the drive (terrain changes)"; }
  std::vector<CandidateParameter> parameters() const override {
    std::vector<CandidateParameter> p;
    p.reserve(static_cast<std::size_t>(windows_));
    for (int k = 0; k < windows_; ++k) p.push_back({"slip_" + std::to_string(k), 0.0, -0.5, 0.9});
    return p;
  }
  estimation::OdometryCorrections corrections(const double* x) const override {
    estimation::OdometryCorrections c;
    c.slip.resize(fit_wheels_.time.size());
    for (std::size_t i = 0; i < c.slip.size(); ++i) {
      const int k =
          std::min(windows_ - 1, static_cast<int>((fit_wheels_.time[i] - fit_wheels_.time.front()) / window_));
      c.slip[i] = x[k];
    }
    return c;
  }
  estimation::OdometryCorrections held_out_corrections(const double* x) const override {
    estimation::OdometryCorrections c;
    std::vector<double> v(x, x + windows_);
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    c.slip.assign(test_n_, v[v.size() / 2]);
    return c;
  }
  // Summarised: the number of windows, the median, least and largest slip.
  std::vector<OdometryParameter> summary(const std::vector<double>& x, const std::vector<double>&) const override {
    std::vector<double> v = x;
    std::sort(v.begin(), v.end());
    return {{"windows", static_cast<double>(x.size()), NAN},
            {"median_slip", v[v.size() / 2], NAN},
            {"min_slip", v.front(), NAN},
            {"max_slip", v.back(), NAN}};
  }

 private:
  const estimation::WheelSamples& fit_wheels_;
  std::size_t test_n_;
  double window_;
  int windows_ = 1;
};

}  // namespace

std::unique_ptr<OdometryCandidateModel> make_slip_episodes_odometry_candidate(const OdometryCandidateContext& c) {
  return std::make_unique<SlipEpisodes>(c);
}

}  // namespace roverlab::analysis
