#include "core/discrepancy/odometry/candidates.h"

namespace roverlab::analysis {

namespace {

// Both sides' wheel radius scaled by one factor.
class RadiusScale final : public OdometryCandidateModel {
 public:
  std::string name() const override { return "radius scale"; }
  std::string cause() const override {
    return "the wheels roll a different distance per turn than the nominal radius says, on both sides (effective "
           "radius, or a steady slip)";
  }
  std::vector<CandidateParameter> parameters() const override { return {{"radius_scale", 1.0, 0.5, 1.5}}; }
  estimation::OdometryCorrections corrections(const double* x) const override {
    estimation::OdometryCorrections c;
    c.radius_scale = x[0];
    return c;
  }
};

}  // namespace

std::unique_ptr<OdometryCandidateModel> make_radius_scale_odometry_candidate(const OdometryCandidateContext&) {
  return std::make_unique<RadiusScale>();
}

}  // namespace roverlab::analysis
