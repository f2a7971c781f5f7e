#include "core/discrepancy/odometry/candidates.h"

namespace roverlab::analysis {

namespace {

// An effective track wider than the geometric one (skid-steer turning).
class TurningTrack final : public OdometryCandidateModel {
 public:
  std::string name() const override { return "turning track"; }
  std::string cause() const override {
    return "skid-steer turning: the wheels skid, so the rover turns less than the wheel-speed difference says";
  }
  std::vector<CandidateParameter> parameters() const override { return {{"track_factor", 1.2, 0.3, 6.0}}; }
  estimation::OdometryCorrections corrections(const double* x) const override {
    estimation::OdometryCorrections c;
    c.track_factor = x[0];
    return c;
  }
};

}  // namespace

std::unique_ptr<OdometryCandidateModel> make_turning_track_odometry_candidate(const OdometryCandidateContext&) {
  return std::make_unique<TurningTrack>();
}

}  // namespace roverlab::analysis
