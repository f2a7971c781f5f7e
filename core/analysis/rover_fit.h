#pragma once
// Least-squares fit of effect parameters of the rover simulation to the fit
// blocks of a log (Ceres, Levenberg-Marquardt, forward differences with each
// parameter's own step: a physical trial is a new simulation), with the
// parameters' 1-sigma from the Gauss-Newton covariance.

#include <vector>

#include "core/analysis/rover_candidates.h"
#include "core/analysis/rover_prediction.h"

namespace roverlab::analysis::rover {

struct FitParameter {
  RoverCandidateParameter spec;
  double value = 0, sigma = 0;
  bool free = true;  // false: held at value (an earlier cause's, or a discrete start)
};

struct FitOutcome {
  std::vector<FitParameter> parameters;
  double chi2_fit = 0, chi2_test = 0;
};

// The scenario's effects with the parameters' values set over them.
simulation::RockerBogieEffects effects_of(const simulation::RockerBogieEffects& scenario,
                                          const std::vector<FitParameter>& parameters);

// Fits the free parameters (spec.fitted and free); the others are held.
FitOutcome fit_parameters(Predictor& predictor, std::vector<FitParameter> parameters);

// Gauss-Newton screen of the free parameters from their values: the
// chi-square on the fit blocks the linearised model predicts at its optimum,
// and that optimum (clamped to the bounds) written into `parameters`.
double linearised_chi2(Predictor& predictor, std::vector<FitParameter>& parameters);

// Sum of squares of the normalised residuals on a part.
double chi2(Predictor& predictor, const simulation::RockerBogieEffects& effects, Part part);

}  // namespace roverlab::analysis::rover
