#pragma once
// What the baseline Wong-Reece model gets wrong on measured single-wheel
// points, which known cause explains it, and what the extended model gains on
// held-out points.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/discrepancy/likelihood.h"
#include "core/discrepancy/study.h"
#include "core/terramechanics/soil_identification.h"

namespace roverlab::analysis {

using terramechanics::Quantity;

struct QuantityResiduals {
  Quantity quantity;
  std::size_t count = 0;
  double rmse = 0.0;
  double bias = 0.0;           // mean(predicted - measured)
  double slope_vs_slip = 0.0;  // residual trend per unit slip (least squares)
  double t_slip = 0.0;         // t statistic of that slope
  double slope_vs_load = 0.0;  // per N
  double t_load = 0.0;
  double t_bias = 0.0;               // bias over its standard error
  double slope_vs_slip_angle = 0.0;  // per rad of slip angle (0 when it does not vary)
  double t_slip_angle = 0.0;
};

// Per measured quantity (issue 29): whether the baseline's error in it is
// more than noise, and which cause, if any, fixes it on held-out points.
struct QuantityVerdict {
  Quantity quantity;
  bool significant = false;    // |t| >= 3 for its bias, its slip trend or its load trend
  std::string explained_by;    // the named cause whose step cut its held-out RMSE >= 30 %; empty: none
  std::string best_candidate;  // the candidate (alone) that predicts it best on held-out points
  double held_out_before = NAN,
         held_out_after = NAN;  // RMSE: baseline, and with explained_by's chain (else best_candidate)
  // The selection step that added explained_by: its chain ("slip-sinkage +
  // slip-shear-modulus") and the held-out RMSE of the step before it.
  std::string explained_by_chain;
  double held_out_step_before = NAN;
  std::string sentence;
};

// Residual statistics per measured quantity, for given predictions.
std::vector<QuantityResiduals> residual_statistics(const std::vector<terramechanics::PointResidual>& residuals,
                                                   const std::vector<terramechanics::WheelTestPoint>& points);

struct CandidateResult {
  std::string name;   // slip-sinkage, grousers, bulldozing, soil-strength
  std::string cause;  // plain words
  bool applicable = true;
  std::string not_applicable_because;
  terramechanics::IdentificationResult fit;  // on all points
  double bic = 0.0;
  double delta_bic = 0.0;                               // against the baseline; negative is better
  std::vector<QuantityResiduals> in_sample;             // residuals of the fit on all points
  std::vector<double> held_out_rmse;                    // per quantity (order of `quantities`), leave-one-out
  double held_out_score = 0.0;                          // RMS of held-out residuals in sigmas
  std::vector<terramechanics::PointResidual> held_out;  // each point's prediction when held out
  // A step of the forward selection (issue 43): its share of the chain's
  // held-out gain (the held-out score it cut against the step before, over
  // the whole chain's cut) and whether it is named: a step under
  // kNegligibleGainShare, or that cuts no quantity's held-out RMSE by 30 %,
  // is "also consistent with". A parameter within 1 % of a bound
  // (near_bound) has no sigma and keeps its candidate from being named.
  double gain_share = NAN;
  StepRole role = StepRole::cause;
};

// Held-out RMSE of one quantity on one wheel's points (wheel tests are
// compared per wheel, e.g. smooth against grousered).
struct WheelHeldOut {
  std::string wheel;  // the wheel's label (its geometry when unlabelled)
  Quantity quantity;
  std::size_t count = 0;
  double baseline_rmse = NAN;  // the baseline's (nothing fitted: in-sample)
  double model_rmse = NAN;     // the study's final model's, held out
};

// What a held-out fold is: points (leave-one-out or k-fold), every point of
// one wheel (a wheel the fit never saw), or every point at one slip.
enum class HoldOut { points, wheel, slip };
HoldOut parse_hold_out(const std::string& text);  // throws DataError

struct DiscrepancyOptions {
  terramechanics::ModelOptions baseline;  // Wong-Reece, Simpson, no extensions
  terramechanics::MeasurementSigma sigma;
  double bic_threshold = -10.0;     // "very strong" evidence (Kass & Raftery 1995)
  double min_held_out_gain = 0.10;  // and at least 10 % lower held-out error
  bool leave_one_out = true;        // false: held-out scores are the in-sample ones
  // Held out: each point alone up to this many points, else `folds` folds
  // (point i in fold i mod folds), so the cost stays linear in the points.
  std::size_t max_leave_one_out_points = 100;
  std::size_t folds = 10;
  // Above this many points, `large_folds` folds (each fold still holds
  // hundreds of points; the refits dominate the study's cost).
  std::size_t large_points = 2000;
  std::size_t large_folds = 5;
  HoldOut hold_out = HoldOut::points;
  // How the file's slip is read at a slip angle (model.h); empty: chosen
  // from the data (study_single_wheel says how).
  std::optional<terramechanics::SlipDefinition> slip_definition;
  std::function<void(double)> progress;  // fraction done; may throw to cancel
  // The model families compared (issue 43): the Wong-Reece / Ishigami
  // family (`baseline`) with nothing fitted, and RFT with its material scale
  // fitted, each held out as a baseline; then the study runs within each, and
  // the family whose final model has the lower held-out error is taken (a
  // family whose baseline loses can win once extended: RFT with a pile-up on
  // a wheel dragged sideways). Off: `baseline` alone (an RFT baseline still
  // has its material scale fitted).
  bool compare_families = false;
  // With more points than this, the family studied second is first studied
  // on a random subset (fixed seed) of this many points, and on all of them only
  // when its final model there holds out better than the first family's
  // final model on all points (a screen: on long files the second family's
  // study would cost as much as the first's). 0: no screen.
  std::size_t family_screen_points = 400;
  // With more points than this, each forward-selection step (after the
  // first) tries every open candidate on a random subset (fixed seed) of this
  // many points, and fits only the `step_screen_keep` best there (by BIC) on
  // all points, the lower BIC on all points taken. 0: every trial on all points.
  std::size_t step_screen_points = 1000;
  std::size_t step_screen_keep = 2;
};

// One model family as the study's baseline (compare_families).
struct FamilyBaseline {
  std::string family;                                          // "Wong-Reece", "Ishigami (slip angle)" or "RFT"
  std::vector<double> held_out_rmse;                           // per quantity (order of `quantities`)
  double held_out_score = NAN;                                 // RMS held-out residual in the stated sigmas
  std::string held_out_method;                                 // "in-sample" (nothing fitted) or "10-fold"
  std::vector<terramechanics::EstimatedParameter> parameters;  // fitted on all points (RFT: rft_scale)
  // The study run within this family: its final model ("baseline" when no
  // step passes) and that model's held-out RMS in the stated sigmas.
  std::string final_model;
  double final_held_out_score = NAN;
  // Those of the study on a random subset of this many points only
  // (family_screen_points); 0: on all points.
  std::size_t studied_points = 0;
  // The points its final model was studied on, of `all`: 0 when the family
  // was not extended.
  std::size_t final_studied_points(std::size_t all) const {
    return studied_points > 0 ? studied_points : final_model.empty() ? 0 : all;
  }
};

struct DiscrepancyReport {
  std::string baseline_model;                  // "Wong-Reece", or "Ishigami (slip angle)" for points at a slip angle
  std::string slip_definition;                 // at a slip angle: "longitudinal" or "travel"; empty otherwise
  std::string slip_definition_reason;          // given by the user, or the evidence that chose it
  std::vector<Quantity> quantities;            // measured in the file
  std::vector<QuantityResiduals> baseline;     // baseline residuals
  std::vector<double> baseline_held_out_rmse;  // = in-sample: nothing is fitted
  double baseline_score = 0.0;                 // RMS residual in sigmas
  double baseline_bic = 0.0;
  std::size_t points = 0, measurements = 0, unsupported = 0;
  std::string
      held_out_method;  // "leave-one-out", "10-fold", "leave-one-wheel-out", "leave-one-slip-out" or "in-sample"
  std::vector<CandidateResult> candidates;
  int best = -1;  // index of the winning candidate, -1 when none is significant
  bool significant = false;
  // Quantities that one candidate predicts much better on held-out points
  // (>= 30 % lower RMSE) even when no candidate explains everything:
  // (quantity, candidate index).
  std::vector<std::pair<Quantity, int>> partial;
  // Forward selection (several causes): each step the chain so far plus one
  // more candidate, all refitted together; empty when no step passes.
  std::vector<CandidateResult> selection;
  // The step screen (DiscrepancyOptions::step_screen_points): each step's
  // trials ranked on a random subset of this many points, its best ones
  // fitted on all; 0: every trial on all points.
  std::size_t step_screen_points = 0;
  // When the first step alone does not pass: the best pair with it, as tried.
  std::optional<CandidateResult> best_pair;
  std::vector<QuantityVerdict> quantity_verdicts;  // one per measured quantity
  std::string final_model;                         // the forward selection's chain, or "baseline"
  std::vector<WheelHeldOut> per_wheel;             // per wheel and quantity, of final_model
  std::string what_is_wrong;                       // one sentence on the baseline's residuals
  std::string verdict;                   // one sentence: the cause and the gain, or "no significant discrepancy"
  std::vector<FamilyBaseline> families;  // the families compared (empty: not compared)
  std::string family_choice;             // the family taken as the baseline, and by how much
  // At a slip angle, when neither the options nor the file state how slip is
  // defined and the two readings differ materially (named causes, or final
  // held-out score by 10 %): this report is the reading's whose final model
  // holds out better (the longitudinal one on a tie) and other_reading holds
  // the other's, each complete (issue 43: no choice between chains of
  // different lengths by BIC).
  std::vector<DiscrepancyReport> other_reading;
};

// The causes a study names (its steps whose role is cause), each step's
// last_link, " + "-joined; empty when it names none.
std::string named_causes(const DiscrepancyReport& r);

// The held-out RMS residual, in the stated sigmas, of a study's final model:
// its last step's, or the baseline's (nothing fitted) when no step passed.
double final_held_out_score(const DiscrepancyReport& r);

// At a slip angle without options.slip_definition the slip's reading is
// chosen from the data (report's slip_definition and its reason).
DiscrepancyReport study_single_wheel(const terramechanics::Soil& soil,
                                     const std::vector<terramechanics::WheelTestPoint>& points,
                                     const DiscrepancyOptions& options = {});

}  // namespace roverlab::analysis
