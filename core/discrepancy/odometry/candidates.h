#pragma once
// The candidate corrections of the odometry discrepancy study: each one a
// class with its name, its cause in plain words, its parameters (start and
// bounds) and the odometry corrections they make. The list is
// odometry_candidates.def; adding a candidate is one file defining its
// factory plus one line there (docs/design.md).

#include <memory>
#include <string>
#include <vector>

#include "core/discrepancy/odometry/study.h"
#include "core/models/skid_steer_odometry.h"

namespace roverlab::analysis {

// A free parameter: its name in the report, start value and bounds.
struct CandidateParameter {
  std::string name;
  double start = 0, lower = 0, upper = 0;
};

// What a candidate may need to know about the study's split.
struct OdometryCandidateContext {
  const estimation::WheelSamples& fit_wheels;  // wheel samples of the fit part
  std::size_t test_wheel_samples = 0;          // number of wheel samples of the test part
  const OdometryStudyOptions& options;
};

class OdometryCandidateModel {
 public:
  virtual ~OdometryCandidateModel() = default;
  virtual std::string name() const = 0;
  virtual std::string cause() const = 0;
  virtual std::vector<CandidateParameter> parameters() const = 0;
  // Corrections from parameters x on the fit part.
  virtual estimation::OdometryCorrections corrections(const double* x) const = 0;
  // Corrections on the held-out part; the fit part's by default.
  virtual estimation::OdometryCorrections held_out_corrections(const double* x) const { return corrections(x); }
  // The fitted parameters as reported; by default each with its sigma.
  virtual std::vector<OdometryParameter> summary(const std::vector<double>& x, const std::vector<double>& sigma) const;
};

// One candidate of each entry in odometry_candidates.def, in its order.
std::vector<std::unique_ptr<OdometryCandidateModel>> odometry_candidates(const OdometryCandidateContext& context);

}  // namespace roverlab::analysis
