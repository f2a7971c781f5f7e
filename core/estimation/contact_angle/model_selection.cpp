#include "core/estimation/contact_angle/model_selection.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <future>
#include <limits>
#include <utility>

#include "core/estimation/contact_angle/streams.h"
#include "core/estimation/contact_angle/two_filter.h"

namespace roverlab::estimation {

const char* to_string(ContactModel model) {
  switch (model) {
    case ContactModel::smooth:
      return "smooth";
    case ContactModel::contact:
      return "c";
    case ContactModel::contact_side_slip:
      return "c+ss";
  }
  return "?";
}

std::pair<double, double> mean_nis_band(double dof, double probability) {
  const double tail = 0.5 * (1.0 - probability);
  return {chi_square_quantile(dof, tail) / dof, chi_square_quantile(dof, 1.0 - tail) / dof};
}

ModelEvidence model_evidence(ContactModel model, const ContactAngleResult& r, const ModelSelectionOptions& s) {
  ModelEvidence e;
  e.model = model;
  e.states = model == ContactModel::smooth ? 12 : model == ContactModel::contact ? 18 : 24;
  e.innovations = r.innovations;
  const InnovationStats& in = r.innovations;
  e.mean_nis = in.dof > 0 ? in.nis_sum / in.dof : NAN;
  // The forward filter's health, as its innovations: a smoothed run's report
  // adds the backward pass's, which a candidate run (--model auto) has not.
  const HealthReport& h = r.smoothed ? r.filter_health : r.health;
  e.nis_out_of_band = h.nis_out_of_band_fraction;
  e.diverged = h.resets > 0 || h.stopped;
  // AIC with the effective degrees of freedom sum tr(H K), on the prediction-error likelihood.
  e.aic = in.updates > 0 && in.effective_dof > 0 ? -2.0 * in.log_likelihood + 2.0 * in.effective_dof
                                                 : std::numeric_limits<double>::infinity();
  // Consistency is the innovations' alone: a run without the effective degrees of freedom (--model set by
  // hand) has no AIC but is judged as the selection judges the same numbers.
  e.consistent =
      in.updates > 0 && e.mean_nis <= s.max_mean_nis && e.nis_out_of_band <= s.max_out_of_band && !e.diverged;
  return e;
}

namespace {

std::string describe(const ModelEvidence& e) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%s: mean NIS %.2f, %.0f %% of windows above band, AIC %.0f%s", to_string(e.model),
                e.mean_nis, 100.0 * e.nis_out_of_band, e.aic, e.diverged ? ", diverged" : "");
  return buf;
}

}  // namespace

ModelSelection select_contact_model(const log::Log& lg, const kinematics::RoverModel& rover,
                                    const ContactAngleOptions& options, const ModelSelectionOptions& s) {
  const ContactModel models[3] = {ContactModel::smooth, ContactModel::contact, ContactModel::contact_side_slip};
  ContactAngleOptions evidence_options = options;
  evidence_options.filter = FilterKind::ekf;  // the fast EKF's innovations decide
  evidence_options.reference_ekf = false;
  evidence_options.effective_dof = true;
  evidence_options.smoother = false;  // the forward pass's innovations are the evidence
  // The two-filter smoother over the fast EKF: the chosen candidate's run is
  // its forward pass (they keep their variances), so only the backward run is added.
  const bool smooth_chosen_run = options.smoother && options.smoother_method == SmootherMethod::two_filter &&
                                 options.filter == FilterKind::ekf && !options.reference_ekf;
  evidence_options.record_variance = smooth_chosen_run;
  std::function<void(double)> progress = options.progress;
  if (smooth_chosen_run && progress) progress = [&options](double f) { options.progress(0.5 * f); };
  ContactAngleResult runs[3];
  const auto run_model = [&](int k, bool with_progress) {
    ContactAngleOptions o = evidence_options;
    o.model = models[k];
    if (with_progress && progress) {
      o.progress = [&progress, k, &s](double f) { progress(s.parallel ? f : (k + f) / 3.0); };
    } else {
      o.progress = nullptr;
    }
    return run_contact_angle(lg, rover, o);
  };
  if (s.parallel) {
    // The first candidate on this thread (it reports progress), the others beside it.
    auto c = std::async(std::launch::async, run_model, 1, false);
    auto css = std::async(std::launch::async, run_model, 2, false);
    runs[0] = run_model(0, true);
    runs[1] = c.get();
    runs[2] = css.get();
  } else {
    for (int k = 0; k < 3; ++k) runs[k] = run_model(k, true);
  }
  ModelSelection out;
  for (int k = 0; k < 3; ++k) out.candidates.push_back(model_evidence(models[k], runs[k], s));
  // The consistent candidate of least AIC; none consistent: the least AIC.
  int best = -1;
  for (int pass = 0; pass < 2 && best < 0; ++pass) {
    for (int k = 0; k < 3; ++k) {
      const ModelEvidence& e = out.candidates[static_cast<std::size_t>(k)];
      if ((pass == 0 && !e.consistent) || !std::isfinite(e.aic)) continue;
      if (best < 0 || e.aic < out.candidates[static_cast<std::size_t>(best)].aic) best = k;
    }
    if (best >= 0) out.supported = pass == 0;
  }
  if (best < 0) best = 1;  // no update at all (standstill throughout): model C, the seed's default
  out.chosen = models[best];
  const ModelEvidence& chosen = out.candidates[static_cast<std::size_t>(best)];
  out.reason =
      std::string("model ") + to_string(out.chosen) +
      (out.supported ? " is the consistent candidate of least AIC (" : ": no candidate is consistent; least AIC (") +
      describe(chosen) + ")";
  if (smooth_chosen_run) {
    ContactAngleOptions o = options;
    o.model = out.chosen;
    out.result = run_contact_angle_two_filter(lg, rover, o, std::move(runs[best]));
    score_contact_angle(lg, out.result);
  } else if (options.filter == FilterKind::ukf || options.reference_ekf || options.smoother) {
    ContactAngleOptions o = options;
    o.model = out.chosen;
    out.result = run_contact_angle(lg, rover, o);
  } else {
    out.result = std::move(runs[best]);
  }
  return out;
}

namespace {
constexpr const char* kLabelEnd = " | ";
}

void label_model(log::Log& estimates, const std::string& label) {
  log::Log out;
  out.metadata = estimates.metadata;
  out.metadata.extra["contact_model"] = label;
  for (const auto& s : estimates.streams()) {
    if (s.name() != contact_streams::kWheels) {
      out.add_stream(s);
      continue;
    }
    log::Stream labelled(s.name(), s.time());
    for (const auto& c : s.channels()) {
      labelled.add_channel(c.name, c.unit, c.values,
                           c.name == "valid" ? label + kLabelEnd + c.description : c.description);
    }
    out.add_stream(std::move(labelled));
  }
  estimates = std::move(out);
}

std::string model_label(const log::Stream& wheels) {
  const log::Channel* valid = wheels.find_channel("valid");
  if (valid == nullptr) return "";
  const auto end = valid->description.find(kLabelEnd);
  return end == std::string::npos ? "" : valid->description.substr(0, end);
}

}  // namespace roverlab::estimation
