#include "core/discrepancy/odometry/candidates.h"

namespace roverlab::analysis {

namespace {

// The left and right wheel radius scaled each by its own factor.
class PerSideScale final : public OdometryCandidateModel {
 public:
  std::string name() const override { return "per-side scale"; }
  std::string cause() const override {
    return "the left and right wheels roll different distances per turn (radius, tyre or encoder scale per side)";
  }
  std::vector<CandidateParameter> parameters() const override {
    return {{"left_scale", 1.0, 0.5, 1.5}, {"right_scale", 1.0, 0.5, 1.5}};
  }
  estimation::OdometryCorrections corrections(const double* x) const override {
    estimation::OdometryCorrections c;
    c.left_scale = x[0];
    c.right_scale = x[1];
    return c;
  }
};

}  // namespace

std::unique_ptr<OdometryCandidateModel> make_per_side_scale_odometry_candidate(const OdometryCandidateContext&) {
  return std::make_unique<PerSideScale>();
}

}  // namespace roverlab::analysis
