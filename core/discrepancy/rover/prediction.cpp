#include "core/discrepancy/rover/prediction.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/common/error.h"
#include "core/log/time_checks.h"

namespace roverlab::analysis::rover {

namespace {

// Every stream the study uses must share the joints' time base: each covers
// at least this share of the other's span, with no gap longer than kMaxGap.
constexpr double kMinOverlap = 0.5;
constexpr double kMaxGap = 1.0;  // s
// No sensor of the rover reads beyond this (SI units: N, N m, rad, m/s, m/s^2).
constexpr double kMaxReading = 1e9;
constexpr std::size_t kMinSamples = 10;

// Clamped linear interpolation of (t, v) at ascending times.
std::vector<double> interpolate_at(const std::vector<double>& t, const std::vector<double>& v,
                                   const std::vector<double>& at) {
  std::vector<double> out(at.size());
  std::size_t j = 0;
  for (std::size_t k = 0; k < at.size(); ++k) {
    const double x = at[k];
    if (x <= t.front()) {
      out[k] = v.front();
      continue;
    }
    if (x >= t.back()) {
      out[k] = v.back();
      continue;
    }
    while (j + 1 < t.size() && t[j + 1] < x) ++j;
    const double w = (x - t[j]) / (t[j + 1] - t[j]);
    out[k] = v[j] + w * (v[j + 1] - v[j]);
  }
  return out;
}

MeasuredChannel measured(const log::Log& lg, const std::string& stream, const std::string& name, double block) {
  const log::Stream* st = lg.find_stream(stream);
  if (st == nullptr)
    throw DataError("no " + stream +
                    " stream (a planar rocker-bogie log has joints, imu, velocimeter, forces and commands)");
  const log::Channel* c = st->find_channel(name);
  if (c == nullptr) throw DataError("stream " + stream + " has no channel " + name);
  log::require_samples(*st, kMinSamples);
  log::require_no_gap(*st, kMaxGap);
  if (const log::Stream* joints = lg.find_stream("joints")) log::require_shared_time_base(*joints, *st, kMinOverlap);
  log::require_finite_within(*st, name, kMaxReading);
  MeasuredChannel m{stream, name, c->unit, st->time(), c->values, {}, 1.0};
  m.fit.resize(m.time.size());
  const double t0 = m.time.front();
  for (std::size_t k = 0; k < m.time.size(); ++k) {
    m.fit[k] = static_cast<std::int64_t>(std::floor((m.time[k] - t0) / block)) % 2 == 0 ? 1 : 0;
  }
  return m;
}

}  // namespace

Predictor::Predictor(const log::Log& lg, const RoverScenarioModel& model, double block) : model_(model) {
  if (!lg.metadata.rover_id.empty() && lg.metadata.rover_id != model.rover) {
    throw DataError("the log's rover is " + lg.metadata.rover_id + ", scenario " + model.name + " models " +
                    model.rover);
  }
  if (lg.find_stream("commands") == nullptr)
    throw DataError("no commands stream (the wheel torques the rover was given)");
  for (const auto& c : simulation::sensor_channels()) {
    channels_.push_back(measured(lg, c.stream, c.name, block));
    channels_.back().integrated = c.integrated;
  }
  for (int i = 1; i <= 3; ++i)
    channels_.push_back(measured(lg, "commands", "wheel_torque_" + std::to_string(i), block));
  const std::vector<double>& t = channels_.front().time;
  duration_ = t.back() - t.front();
  if (!(duration_ >= 8 * block)) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "the log lasts %.3g s; the study needs at least 8 blocks of %.3g s (4 to fit, 4 to test)", duration_,
                  block);
    throw DataError(text);
  }
}

const Simulated& Predictor::simulate(const simulation::RockerBogieEffects& fx) {
  // Only the physical effects change the run; the sensor effects are applied to its series.
  simulation::RockerBogieEffects physical;
  physical.soil_strength = fx.soil_strength;
  physical.slip_sinkage_n1 = fx.slip_sinkage_n1;
  physical.grouser_height = fx.grouser_height;
  physical.wheel_radius_scale = fx.wheel_radius_scale;
  physical.effect_start_x = fx.effect_start_x;
  physical.slip_angle_deg = fx.slip_angle_deg;
  const std::array<double, 6> key{physical.soil_strength,      physical.slip_sinkage_n1, physical.grouser_height,
                                  physical.wheel_radius_scale, physical.effect_start_x,  physical.slip_angle_deg};
  used_.push_back(key);
  auto it = cache_.find(key);
  if (it != cache_.end()) {
    touch(key);
    return *it->second;
  }
  simulation::RockerBogieRun run = model_.run;
  run.duration = channels_.front().time.back();
  run.sensor_noise = false;
  run.refuse_unsupported_soil = false;
  run.progress = nullptr;
  run.effects = physical;
  const simulation::RockerBogieResult r = simulation::simulate_rocker_bogie(model_.geometry, model_.parameters, run);
  ++simulations_;
  Simulated s;
  const auto& names = simulation::sensor_channels();
  for (std::size_t c = 0; c < simulation::kSensorChannels; ++c) {
    s.sensors.values[c] = r.log.stream(names[c].stream).channel(names[c].name).values;
  }
  s.sensors.time = r.log.stream("joints").time();
  s.sensors.imu_time = s.sensors.time;
  for (std::size_t i = 0; i < 3; ++i) {
    s.torque[i] = r.log.stream("commands").channel("wheel_torque_" + std::to_string(i + 1)).values;
  }
  s.front_x = r.log.stream("truth/wheels").channel("centre_x_1").values;
  auto stored = std::make_shared<const Simulated>(std::move(s));
  remember(key, stored);
  return *stored;
}

// The least recently used runs go first, within about 256 MB (a fit's
// second pass and the sigmas' profile come back to the runs of its first:
// clearing all 17 at once made the README's study simulate 13 of its 53
// runs twice; issue 34, N8).
void Predictor::remember(const Key& key, std::shared_ptr<const Simulated> run) {
  const double run_bytes = 8.0 * double(simulation::kSensorChannels + 6) * double(channels_.front().time.size());
  const std::size_t keep = std::clamp<std::size_t>(static_cast<std::size_t>(256e6 / std::max(run_bytes, 1.0)), 4, 64);
  while (cache_.size() >= keep) {
    cache_.erase(cache_order_.front());
    cache_order_.pop_front();
  }
  cache_order_.push_back(key);
  cache_.emplace(key, std::move(run));
}

void Predictor::touch(const Key& key) {
  cache_order_.erase(std::find(cache_order_.begin(), cache_order_.end(), key));
  cache_order_.push_back(key);
}

Predictor Predictor::fork() const {
  Predictor copy = *this;
  copy.simulations_ = 0;
  copy.used_.clear();
  return copy;
}

void Predictor::absorb(const Predictor& other) {
  for (const Key& key : other.used_) {
    if (cache_.count(key) != 0) {
      touch(key);
    } else if (const auto it = other.cache_.find(key); it != other.cache_.end()) {
      remember(key, it->second);
    } else {
      continue;  // the fork let it go too
    }
    used_.push_back(key);
  }
  simulations_ += other.simulations_;
}

std::array<std::vector<double>, kChannels> Predictor::predict(const simulation::RockerBogieEffects& fx) {
  const Simulated& sim = simulate(fx);
  simulation::SensorSeries series = sim.sensors;
  simulation::apply_sensor_effects(fx, series);
  std::array<std::vector<double>, kChannels> out;
  for (std::size_t c = 0; c < kChannels; ++c) {
    const bool sensor = c < simulation::kSensorChannels;
    const std::vector<double>& t = sensor && channels_[c].stream == "imu" ? series.imu_time : series.time;
    const std::vector<double>& v = sensor ? series.values[c] : sim.torque[c - simulation::kSensorChannels];
    out[c] = interpolate_at(t, v, channels_[c].time);
  }
  return out;
}

std::vector<double> Predictor::residuals(const simulation::RockerBogieEffects& fx, Part part) {
  const auto p = predict(fx);
  std::vector<double> r;
  r.reserve(count(part));
  for (std::size_t c = 0; c < kChannels; ++c) {
    const MeasuredChannel& m = channels_[c];
    for (std::size_t k = 0; k < m.values.size(); ++k) {
      if (part == Part::all || (m.fit[k] != 0) == (part == Part::fit)) r.push_back((m.values[k] - p[c][k]) / m.sigma);
    }
  }
  return r;
}

std::size_t Predictor::count(Part part) const {
  std::size_t n = 0;
  for (const auto& m : channels_) {
    for (char f : m.fit) n += part == Part::all || (f != 0) == (part == Part::fit) ? 1 : 0;
  }
  return n;
}

const GroupedLikelihood& Predictor::likelihood(Part part) {
  auto it = likelihoods_.find(part);
  if (it != likelihoods_.end()) return it->second;
  std::vector<ResidualGroup> groups;
  std::vector<char> start;
  for (const MeasuredChannel& m : channels_) {
    ResidualGroup g{m.stream + "/" + m.name, 0, m.integrated, m.resolution / m.sigma, true};
    bool previous_in = false;
    for (char f : m.fit) {
      const bool in = part == Part::all || (f != 0) == (part == Part::fit);
      if (in) {
        start.push_back(previous_in ? 0 : 1);
        ++g.size;
      }
      previous_in = in;
    }
    groups.push_back(std::move(g));
  }
  return likelihoods_.emplace(part, GroupedLikelihood(std::move(groups), std::move(start))).first->second;
}

}  // namespace roverlab::analysis::rover
