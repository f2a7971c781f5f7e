#pragma once
// Model C, C+SS or smooth chosen by the data (issue 15, not in seed 000: the
// seed picks the model per scenario by hand). Each candidate runs over the
// log; its measurement innovations are the evidence: their consistency (the
// mean normalised innovation squared against its chi-square band, and the
// share of 2 s NIS windows above theirs) and a penalised likelihood: the
// innovations' Gaussian log-likelihood (the prediction-error decomposition)
// penalised by the filter's effective degrees of freedom, the sum over the
// updates of tr(H K), the hat matrix's trace (Hodges and Sargent 2001): a
// random-walk state the data do not need still absorbs part of every
// measurement, and pays for it. AIC = -2 ln L + 2 edf.

#include <string>
#include <vector>

#include "core/estimation/contact_angle/contact_angle.h"
#include "core/kinematics/rover_model.h"
#include "core/log/log.h"

namespace roverlab::estimation {

struct ModelEvidence {
  ContactModel model = ContactModel::contact;
  int states = 0;               // filter states
  InnovationStats innovations;  // of the run
  double mean_nis = 0;          // NIS per degree of freedom; 1 for a consistent filter
  double nis_out_of_band = 0;   // share of NIS windows above their band (HealthReport)
  bool diverged = false;        // the run was reset or stopped
  double aic = 0;               // -2 ln L + 2 edf, edf = innovations.effective_dof
  bool consistent = false;      // mean NIS within the band, few windows above theirs, not diverged
};

struct ModelSelectionOptions {
  // Consistency: mean NIS per degree of freedom at most this (the seed's
  // tuning overstates the noises: a model the data support stays below 1),
  // and at most this share of 2 s windows above their 99.9 % chi-square
  // band (0.1 % for a consistent filter; a smooth model on a rotating
  // bogie puts a fifth to a third of them above).
  double max_mean_nis = 2.0;
  double max_out_of_band = 0.05;
  bool parallel = true;  // the candidates in threads
};

struct ModelSelection {
  ContactModel chosen = ContactModel::contact;
  std::vector<ModelEvidence> candidates;  // smooth, C, C+SS
  bool supported = true;                  // false: every candidate was inconsistent; the least AIC is shown
  std::string reason;                     // one sentence
  ContactAngleResult result;              // the chosen model's run
};

// Runs smooth, C and C+SS with `options` (its model ignored; the UKF, the
// reference EKF and the smoother run the chosen model again after the
// selection by the fast EKF's forward-pass evidence), picks the consistent candidate of least AIC (none
// consistent: the least AIC, supported false). Throws as run_contact_angle.
ModelSelection select_contact_model(const log::Log& log, const kinematics::RoverModel& rover,
                                    const ContactAngleOptions& options, const ModelSelectionOptions& selection = {});

// One run's evidence (its model as run); consistent as the selection judges.
ModelEvidence model_evidence(ContactModel model, const ContactAngleResult& run,
                             const ModelSelectionOptions& selection = {});

// The chi-square band of a mean NIS per dof over `dof` degrees of freedom at
// two-sided probability p: [lower, upper].
std::pair<double, double> mean_nis_band(double dof, double probability = 0.95);

const char* to_string(ContactModel model);  // smooth | c | c+ss

// Names the model on the estimate streams (views say which model they show):
// the wheels stream's "model" description, set on its "valid" channel as
// "<label>; <the channel's description>". model_label() reads it back (empty
// when absent).
void label_model(log::Log& estimates, const std::string& label);
std::string model_label(const log::Stream& wheels);

}  // namespace roverlab::estimation
