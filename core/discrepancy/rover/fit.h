#pragma once
// Least-squares fit of effect parameters of the rover simulation to the fit
// blocks of a log (Ceres, Levenberg-Marquardt, forward differences with each
// parameter's own step: a physical trial is a new simulation; a single
// parameter's Jacobian then follows secants, JacobianMemo), on residuals
// whitened by the study's likelihood (likelihood.h) at the profile of the
// model the parameters are added to, with the parameters' 1-sigma from the
// Gauss-Newton covariance of the residuals whitened at the solution's
// profile. Every score is -2 ln L of that likelihood (noise scale and
// autocorrelation per channel profiled out).

#include <vector>

#include "core/discrepancy/rover/candidates.h"
#include "core/discrepancy/rover/prediction.h"

namespace roverlab::analysis::rover {

struct FitParameter {
  RoverCandidateParameter spec;
  double value = 0, sigma = 0;
  bool free = true;  // false: held at value (an earlier cause's, or a discrete start)
};

// A model's score on the log.
struct Score {
  double fit = 0, test = 0;   // -2 ln L on the fit and the test blocks
  double held_out = 0;        // RMS normalised residual on the test blocks (increments for encoders), in noise sigmas
  LikelihoodProfile profile;  // on the fit blocks
  LikelihoodProfile weights;  // on the fit blocks: the weights of a fit started here (fit_weights)
};

// The raw (unwhitened) Jacobian of the fit blocks' residuals in the free
// parameters and where it was formed, carried from a candidate's screen
// through its fit's passes: every forward difference is a whole simulation
// (issue 34, N8). Valid while the free parameters and the held values stay.
struct JacobianMemo {
  std::vector<double> x, r, raw;  // the point, the raw residuals there, the Jacobian (n x m, row-major)
};

struct FitOutcome {
  std::vector<FitParameter> parameters;
  Score score;
};

// The scenario's effects with the parameters' values set over them.
simulation::RockerBogieEffects effects_of(const simulation::RockerBogieEffects& scenario,
                                          const std::vector<FitParameter>& parameters);

// Fits the free parameters (spec.fitted and free); the others are held.
// `weights`: the profile of the model they are added to.
// `memo`: a Jacobian formed before (the screen's), read and updated.
FitOutcome fit_parameters(Predictor& predictor, std::vector<FitParameter> parameters, const LikelihoodProfile& weights,
                          bool with_sigmas = true, JacobianMemo* memo = nullptr);

// The fitted parameters' +-1 sigma from the profile likelihood's curvature
// at their values, where -2 ln L on the fit blocks is minus_two_log_l.
void set_sigmas(Predictor& predictor, std::vector<FitParameter>& parameters, double minus_two_log_l);

// Gauss-Newton screen of the free parameters from their values: -2 ln L on
// the fit blocks that the linearised model predicts at its optimum, and that
// optimum (clamped to the bounds) written into `parameters`.
// `memo` receives the Jacobian at the start.
double linearised_fit(Predictor& predictor, std::vector<FitParameter>& parameters, const LikelihoodProfile& weights,
                      JacobianMemo& memo);

// Moves each free parameter with a grid step to the best point of its grid
// (-2 ln L on the fit blocks, the others held at their values); a
// grid_screen parameter (one basin) walks up from its lower bound and stops
// where -2 ln L stops falling.
void grid_start(Predictor& predictor, std::vector<FitParameter>& parameters);

// A model's score (the channels' sigmas must be set).
Score score(Predictor& predictor, const simulation::RockerBogieEffects& effects);

}  // namespace roverlab::analysis::rover
