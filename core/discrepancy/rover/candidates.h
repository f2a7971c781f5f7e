#pragma once
// The candidate causes of the rover discrepancy study: each one a class with
// its name, its cause in plain words and the effects of the planar
// rocker-bogie simulation (RockerBogieEffects, set by name through
// simulation::set_effect) it frees. The list is rover_candidates.def; adding
// a candidate is one file rover_candidate_X.cpp plus one line there.

#include <cmath>
#include <memory>
#include <string>
#include <vector>

namespace roverlab::analysis {

// What the study reads off the baseline residuals before fitting, for
// candidates whose start cannot be a fixed number.
struct RoverResidualFeatures {
  double change_time = NAN;  // s: where the logged torques start to depart from the simulation's
  double change_x = NAN;     // m: the front wheel's x in the baseline simulation at change_time
  double hold_start = NAN;   // s: first time the wheel encoders stop changing for 1 s or more (NaN: never)
  bool from_start = false;   // the torques depart within the first 2 s: a change over the whole run
  // Mean slip over the run, velocimeter against encoders: measured, and the nominal simulation's.
  double measured_slip = NAN, model_slip = NAN;
};

struct RoverCandidateParameter {
  std::string effect;  // simulation::set_effect name
  std::string unit;
  double start = 0, lower = 0, upper = 0;
  double step = 0;           // finite-difference step of the fit
  bool fitted = true;        // false: set from the residual features and held (a discrete start time)
  double resolution = 0;     // stated 1-sigma of a held parameter
  double grid = 0;           // > 0: the fit starts at the best of a grid of this step over the bounds (a
                             // position whose likelihood is too sharply peaked for a local start)
  bool grid_screen = false;  // the screen's Gauss-Newton step also starts at the grid's best (a response far
                             // from linear in the parameter, as the drawbar pull's in a slip angle, ~ beta^2)
};

class RoverCandidate {
 public:
  virtual ~RoverCandidate() = default;
  virtual const char* name() const = 0;
  virtual const char* cause() const = 0;
  // Whether a trial value needs a new simulation (a physical effect) or only
  // the sensor effects applied to the one it has (a sensor effect).
  virtual bool physical() const = 0;
  // Its parameters with starts taken from the features where it needs them;
  // empty when the features say it cannot apply (no hold in the encoders).
  virtual std::vector<RoverCandidateParameter> parameters(const RoverResidualFeatures& features) const = 0;
};

// A candidate whose parameters do not depend on the residual features.
std::unique_ptr<RoverCandidate> fixed_rover_candidate(const char* name, const char* cause, bool physical,
                                                      std::vector<RoverCandidateParameter> parameters);

// One candidate of each entry in rover_candidates.def, in its order.
std::vector<std::unique_ptr<RoverCandidate>> rover_candidates();

}  // namespace roverlab::analysis
