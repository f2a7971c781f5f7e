#include "core/discrepancy/rover/study.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/common/error.h"
#include "core/common/thread_pool.h"
#include "core/discrepancy/rover/candidates.h"
#include "core/discrepancy/rover/fit.h"
#include "core/discrepancy/rover/prediction.h"
#include "core/discrepancy/study.h"

namespace roverlab::analysis {

using namespace rover;

namespace {

using Prediction = std::array<std::vector<double>, kChannels>;

// The resolution below which a channel's noise is not trusted: a torque
// command is known to 5 mN m, an encoder to 0.1 urad (below the Kapvik
// encoders' 0.37 urad, seed 003 Table 5.1: at 1 urad their scale sat on the
// floor and the fit weighed them 7 times less than their noise allows), a
// force to 1 mN.
double noise_floor(const std::string& unit) {
  if (unit == "rad") return 1e-7;
  if (unit == "N") return 1e-3;
  if (unit == "N*m") return 5e-3;
  return 1e-4;  // rad/s, m/s^2, m/s
}

double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

// Each channel's noise from the baseline residual's sample-to-sample
// differences (robust: the median absolute deviation), floored.
void set_noise(std::vector<MeasuredChannel>& channels, const Prediction& p) {
  for (std::size_t c = 0; c < kChannels; ++c) {
    MeasuredChannel& m = channels[c];
    std::vector<double> d(m.values.size() - 1);
    for (std::size_t k = 1; k < m.values.size(); ++k)
      d[k - 1] = (m.values[k] - p[c][k]) - (m.values[k - 1] - p[c][k - 1]);
    const double md = median(d);
    for (double& x : d) x = std::abs(x - md);
    m.resolution = noise_floor(m.unit);
    m.sigma = std::max(1.4826 * median(d) / std::sqrt(2.0), m.resolution);
  }
}

// Mean wheel slip from the sensors alone: 1 - v / (r w), w the wheels' mean
// rate over 1 s; NaN where the wheels barely turn.
std::vector<double> sensor_slip(const std::vector<MeasuredChannel>& ch, double radius) {
  const std::vector<double>& t = ch[7].time;
  std::vector<double> s(t.size(), NAN);
  const std::size_t h = 25;
  for (std::size_t k = h; k + h < t.size() && k + h < ch[1].values.size(); ++k) {
    double w = 0;
    for (std::size_t i = 1; i <= 3; ++i)
      w += (ch[i].values[k + h] - ch[i].values[k - h]) / (ch[i].time[k + h] - ch[i].time[k - h]);
    w /= 3;
    if (std::abs(w * radius) > 1e-3) s[k] = 1 - ch[7].values[k] / (w * radius);
  }
  return s;
}

// Where the simulation starts to disagree with the logged torques: the first
// sample from which some torque command's residual stays beyond 3 sigma for
// 5 samples. Only a physical cause moves the torques (sensor effects leave
// them alone), so this is where a soil change, if any, begins. NaN: never.
double change_time(const std::vector<MeasuredChannel>& ch, const Prediction& p) {
  double first = NAN;
  for (std::size_t c = simulation::kSensorChannels; c < kChannels; ++c) {
    int run = 0;
    for (std::size_t k = 0; k < ch[c].values.size(); ++k) {
      run = std::abs(ch[c].values[k] - p[c][k]) > 3 * ch[c].sigma ? run + 1 : 0;
      if (run == 5) {
        const double t = ch[c].time[k - 4];
        if (!(t >= first)) first = t;
        break;
      }
    }
  }
  return first;
}

// The first time the wheel encoders all stop changing for 1 s or more.
double hold_start(const std::vector<MeasuredChannel>& ch) {
  const std::vector<double>& t = ch[1].time;
  std::size_t start = 0;
  for (std::size_t k = 1; k < t.size(); ++k) {
    bool held = true;
    for (std::size_t i = 1; i <= 3; ++i) held = held && ch[i].values[k] == ch[i].values[k - 1];
    if (!held) {
      start = k;
      continue;
    }
    // The dropout began between the last changing sample and the first held one.
    if (t[k] - t[start] >= 1.0) return 0.5 * (t[start] + t[start + 1]);
  }
  return NAN;
}

RoverResidualFeatures features(const std::vector<MeasuredChannel>& ch, const Prediction& p, const Simulated& base) {
  RoverResidualFeatures f;
  f.change_time = change_time(ch, p);
  f.from_start = f.change_time < ch.front().time.front() + 2.0;
  if (std::isfinite(f.change_time)) {
    f.change_x = log::interpolate_linear(base.sensors.time, base.front_x, f.change_time);
  }
  f.hold_start = hold_start(ch);
  return f;
}

void channel_statistics(RoverDiscrepancyReport& r, const std::vector<MeasuredChannel>& ch, const Prediction& p,
                        const std::vector<double>& slip, const Simulated& base) {
  for (std::size_t c = 0; c < kChannels; ++c) {
    const MeasuredChannel& m = ch[c];
    RoverChannelResiduals s;
    s.stream = m.stream;
    s.channel = m.name;
    s.unit = m.unit;
    s.sigma = m.sigma;
    std::vector<double> res(m.values.size()), t100(m.values.size()), x(m.values.size()), sl(m.values.size(), NAN),
        load(m.values.size(), NAN);
    double sum = 0;
    for (std::size_t k = 0; k < res.size(); ++k) {
      res[k] = m.values[k] - p[c][k];
      sum += res[k];
      t100[k] = m.time[k] / 100.0;
      x[k] = log::interpolate_linear(base.sensors.time, base.front_x, m.time[k]);
      if (slip.size() == res.size()) sl[k] = slip[k];
      if (ch[8].values.size() == res.size()) load[k] = (ch[8].values[k] + ch[9].values[k] + ch[10].values[k]) / 3;
    }
    const auto n = static_cast<double>(res.size());
    s.bias = sum / n;
    s.rmse = rmse(res);
    const Trend dt = regress(t100, res), ds = regress(sl, res), dx = regress(x, res), dl = regress(load, res);
    s.drift = dt.slope;
    s.t_drift = dt.t;
    s.slope_vs_slip = ds.slope;
    s.t_slip = ds.t;
    s.slope_vs_position = dx.slope;
    s.t_position = dx.t;
    s.slope_vs_load = dl.slope;
    s.t_load = dl.t;
    r.channels.push_back(s);
  }
}

// Held-out RMSE per channel, in the channel's unit.
void held_out_rmse(RoverDiscrepancyReport& r, const std::vector<MeasuredChannel>& ch, const Prediction& p, bool after) {
  for (std::size_t c = 0; c < kChannels; ++c) {
    std::vector<double> e;
    for (std::size_t k = 0; k < ch[c].values.size(); ++k) {
      if (ch[c].fit[k] == 0) e.push_back(ch[c].values[k] - p[c][k]);
    }
    (after ? r.channels[c].held_out_rmse_after : r.channels[c].held_out_rmse_before) = rmse(e);
  }
}

// Held-out RMS per channel in noise sigmas, as the study's held-out figure
// counts them (likelihood.h's groups on the test blocks; encoders as
// increments, whose noise is sqrt(2) sigmas; no autocorrelation removed).
void held_out_sigmas(RoverDiscrepancyReport& r, Predictor& pr, const std::vector<FitParameter>& chain, bool after) {
  const GroupedLikelihood& l = pr.likelihood(Part::test);
  const std::vector<double> res = pr.residuals(effects_of(pr.scenario_effects(), chain), Part::test);
  const LikelihoodProfile counts = l.profile(res);  // each group's residuals with their lags
  LikelihoodProfile yardstick;
  for (const auto& g : l.groups()) yardstick.groups.push_back({0.0, g.integrated ? std::sqrt(2.0) : 1.0, 0});
  std::vector<double> w(l.effective_count());
  l.whiten(yardstick, res.data(), w.data());
  std::size_t j = 0;
  for (std::size_t c = 0; c < l.groups().size() && c < r.channels.size(); ++c) {
    const std::size_t n = counts.groups[c].used;
    const auto from = w.begin() + static_cast<std::ptrdiff_t>(j);
    j += n;
    (after ? r.channels[c].held_out_sigmas_after : r.channels[c].held_out_sigmas_before) =
        rmse(std::vector<double>(from, from + static_cast<std::ptrdiff_t>(n)));
  }
}

// RMS over channels of the normalised residual at each sample (channels on the first channel's time base).
std::vector<double> residual_series(const std::vector<MeasuredChannel>& ch, const Prediction& p) {
  const std::size_t n = ch[0].values.size();
  std::vector<double> out(n, 0.0);
  double used = 0;
  for (std::size_t c = 0; c < kChannels; ++c) {
    if (ch[c].values.size() != n) continue;
    used += 1;
    for (std::size_t k = 0; k < n; ++k) {
      const double z = (ch[c].values[k] - p[c][k]) / ch[c].sigma;
      out[k] += z * z;
    }
  }
  for (double& v : out) v = std::sqrt(v / std::max(used, 1.0));
  return out;
}

}  // namespace

// Defined in rover_discrepancy_checks.cpp, _traction.cpp and _selection.cpp.
namespace rover {
std::vector<RoverRedundancyCheck> redundancy_checks(const std::vector<MeasuredChannel>& channels,
                                                    const RoverScenarioModel& model);
std::vector<RoverRedundancyCheck> traction_checks(const log::Log& log, const RoverScenarioModel& model);
RoverSlipRegime slip_regime(const std::vector<MeasuredChannel>& channels, double radius);
RoverRedundancyCheck slip_check(const std::vector<MeasuredChannel>& channels, const RoverSlipRegime& measured,
                                const std::array<std::vector<double>, kChannels>& predicted, double radius);
void select_causes(Predictor& predictor, const RoverResidualFeatures& features, const RoverStudyOptions& options,
                   RoverDiscrepancyReport& report, std::vector<FitParameter>& chain);
void write_verdict(RoverDiscrepancyReport& report);
}  // namespace rover

RoverDiscrepancyReport study_rover(const log::Log& lg, const RoverScenarioModel& model,
                                   const RoverStudyOptions& options) {
  if (!(options.block > 0)) throw DataError("the fit/test block must be longer than 0 s");
  Predictor predictor(lg, model, options.block);
  RoverDiscrepancyReport r;
  r.scenario = model.name;
  r.duration = predictor.duration();
  r.drive = "the simulation is driven by the controller's set points (desired speed " +
            std::to_string(model.parameters.desired_speed) + " m/s); the logged torques are compared with its torques";
  char method[200];
  std::snprintf(method, sizeof method, "alternating blocks of %.3g s: even blocks fit, odd blocks test", options.block);
  r.held_out_method = method;
  const simulation::RockerBogieEffects& none = predictor.scenario_effects();  // the nominal model
  // The baseline simulation and the net-traction check (an estimator over
  // the log, as long as a simulation) share nothing: side by side.
  Prediction p0;
  std::vector<RoverRedundancyCheck> traction;
  shared_thread_pool().run_beside([&] { traction = traction_checks(lg, model); },
                                  [&] { p0 = predictor.predict(none); });
  set_noise(predictor.channels(), p0);
  const Simulated& base = predictor.simulate(none);
  const std::vector<double> slip = sensor_slip(predictor.channels(), model.geometry.wheel_radius);
  channel_statistics(r, predictor.channels(), p0, slip, base);
  held_out_rmse(r, predictor.channels(), p0, false);
  held_out_sigmas(r, predictor, {}, false);
  r.checks = redundancy_checks(predictor.channels(), model);
  r.slip_regime = slip_regime(predictor.channels(), model.geometry.wheel_radius);
  r.checks.push_back(slip_check(predictor.channels(), r.slip_regime, p0, model.geometry.wheel_radius));
  const double slip_check_model = r.checks.back().expected;
  for (auto& c : traction) r.checks.push_back(std::move(c));
  r.fit_residuals = predictor.count(Part::fit);
  r.test_residuals = predictor.count(Part::test);
  RoverResidualFeatures f = features(predictor.channels(), p0, base);
  f.measured_slip = r.slip_regime.mean_slip;
  f.model_slip = slip_check_model;
  std::vector<FitParameter> chain;
  select_causes(predictor, f, options, r, chain);
  const Prediction p1 = predictor.predict(effects_of(predictor.scenario_effects(), chain));
  held_out_rmse(r, predictor.channels(), p1, true);
  held_out_sigmas(r, predictor, chain, true);
  for (std::size_t c = 0; c < kChannels && c < r.channels.size(); ++c) {
    r.channels[c].time = predictor.channels()[c].time;
    r.channels[c].predicted_before = p0[c];
    r.channels[c].predicted_after = p1[c];
  }
  r.time = predictor.channels()[0].time;
  r.residual_before = residual_series(predictor.channels(), p0);
  r.residual_after = residual_series(predictor.channels(), p1);
  r.slip = slip.size() == r.time.size() ? slip : std::vector<double>(r.time.size(), NAN);
  r.simulations = predictor.simulations();
  write_verdict(r);
  return r;
}

}  // namespace roverlab::analysis
