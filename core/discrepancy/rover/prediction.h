#pragma once
// The rover discrepancy study's model side: the measured channels of a
// planar rocker-bogie log, the noise-free simulation of the scenario under
// trial effects interpolated at their time stamps (physical effects by a new
// simulation, cached; sensor effects by simulation::apply_sensor_effects),
// and the residuals normalised by each channel's noise on the fit or the
// test blocks.

#include <array>
#include <cstddef>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/discrepancy/likelihood.h"
#include "core/discrepancy/rover/study.h"
#include "core/simulation/sensor_effects.h"

namespace roverlab::analysis::rover {

constexpr std::size_t kChannels = simulation::kSensorChannels + 3;  // the sensors, then wheel_torque_1..3

struct MeasuredChannel {
  std::string stream, name, unit;
  std::vector<double> time, values;
  std::vector<char> fit;     // 1: the sample is in a fit block, 0: in a test block
  double sigma = 1;          // noise of one sample, the residuals' unit
  double resolution = 1e-4;  // the smallest noise trusted (unit)
  bool integrated = false;   // an angle integrated from a rate: compared as increments
};

// A noise-free simulation without sensor effects.
struct Simulated {
  simulation::SensorSeries sensors;
  std::array<std::vector<double>, 3> torque;
  std::vector<double> front_x;  // m, wheel 1's centre
};

enum class Part { fit, test, all };

class Predictor {
 public:
  // Throws DataError naming what the log lacks.
  Predictor(const log::Log& log, const RoverScenarioModel& model, double block);

  const std::vector<MeasuredChannel>& channels() const { return channels_; }
  std::vector<MeasuredChannel>& channels() { return channels_; }
  double duration() const { return duration_; }
  // The scenario's own effects: part of the model, the start of every trial.
  const simulation::RockerBogieEffects& scenario_effects() const { return model_.run.effects; }
  int simulations() const { return simulations_; }
  // A copy for one independent part of the study (a candidate's trial, run
  // on its own thread): it shares the runs simulated so far (read-only) and
  // counts only its own simulations.
  Predictor fork() const;
  // Replays the runs `other` (a fork) used, in their order: one this
  // predictor lacks is taken, one it has becomes as recent as there (not
  // the runs the fork only inherited: those this one may have let go since);
  // and counts its simulations. Forks absorbed in a fixed order leave the
  // same cache on any number of threads.
  void absorb(const Predictor& other);

  // The simulation under `effects` (physical part cached).
  const Simulated& simulate(const simulation::RockerBogieEffects& effects);
  // Predicted values of every channel at its measured time stamps.
  std::array<std::vector<double>, kChannels> predict(const simulation::RockerBogieEffects& effects);
  // (measured - predicted) / sigma over the chosen part, channel after channel.
  std::vector<double> residuals(const simulation::RockerBogieEffects& effects, Part part);
  std::size_t count(Part part) const;
  // The likelihood of residuals(effects, part) (part fit or test): a group
  // per channel, blocks as segments. Built on first use: set the channels'
  // sigmas first.
  const GroupedLikelihood& likelihood(Part part);

 private:
  const RoverScenarioModel& model_;
  std::vector<MeasuredChannel> channels_;
  double duration_ = 0;
  int simulations_ = 0;
  using Key = std::array<double, 6>;
  void remember(const Key& key, std::shared_ptr<const Simulated> run);
  std::map<Key, std::shared_ptr<const Simulated>> cache_;
  std::deque<std::array<double, 6>> cache_order_;  // least recently used first
  std::vector<Key> used_;                          // every run asked for (since the fork), in order
  void touch(const Key& key);                      // key (cached) becomes the most recently used
  std::map<Part, GroupedLikelihood> likelihoods_;
};

}  // namespace roverlab::analysis::rover
