#include "core/estimation/contact_angle/estimate_errors.h"
#include "core/estimation/contact_angle/streams.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace roverlab::analysis {

AlignedTruth align_truth(const log::Stream& truth, const std::vector<double>& estimate_time) {
  AlignedTruth a;
  a.truth = &truth;
  a.index.resize(estimate_time.size());
  for (std::size_t i = 0; i < estimate_time.size(); ++i) a.index[i] = truth.nearest_index(estimate_time[i]);
  return a;
}

std::vector<char> moving_samples(const log::Stream& estimate, std::string_view valid_channel, const AlignedTruth& body,
                                 std::string_view truth_vx, std::string_view truth_vy, double min_speed) {
  const std::vector<double>* valid = valid_channel.empty() ? nullptr : &estimate.channel(valid_channel).values;
  const auto& vx = body.truth->channel(truth_vx).values;
  const auto& vy = body.truth->channel(truth_vy).values;
  std::vector<char> mask(estimate.size(), 0);
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (valid != nullptr && (*valid)[i] == 0.0) continue;
    const std::size_t k = body.index[i];
    if (std::hypot(vx[k], vy[k]) < min_speed) continue;
    mask[i] = 1;
  }
  return mask;
}

double squared_error_sum(const std::vector<double>& estimate, const AlignedTruth& truth, std::string_view truth_channel,
                         const std::vector<char>& mask) {
  const auto& tv = truth.truth->channel(truth_channel).values;
  double sum = 0;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (mask[i] != 0) sum += std::pow(estimate[i] - tv[truth.index[i]], 2);
  }
  return sum;
}

double rms_error(const log::Stream& estimate, std::string_view estimate_channel, const AlignedTruth& truth,
                 std::string_view truth_channel, const std::vector<char>& mask, std::size_t samples) {
  const double sum = squared_error_sum(estimate.channel(estimate_channel).values, truth, truth_channel, mask);
  return std::sqrt(sum / static_cast<double>(std::max<std::size_t>(samples, 1)));
}

namespace {

// Whether t lies within the truth stream's span, widened by one mean sample
// interval at each end.
bool within_span(const log::Stream& truth, double t) {
  const double margin = truth.size() > 1 ? truth.duration() / static_cast<double>(truth.size() - 1) : 0.0;
  return t >= truth.start_time() - margin && t <= truth.end_time() + margin;
}

}  // namespace

std::optional<estimation::StateErrors> contact_angle_errors(const log::Log& lg, const log::Log& estimates) {
  const log::Stream* tb = lg.find_stream("truth/body");
  const log::Stream* tw = lg.find_stream("truth/wheels");
  if (tb == nullptr || tw == nullptr) return std::nullopt;
  const log::Stream& body = estimates.stream(estimation::contact_streams::kBody);
  const log::Stream& wheels = estimates.stream(estimation::contact_streams::kWheels);
  // Scored only where truth exists: an empty truth stream, or one recorded
  // at other times than the estimate, scores nothing.
  if (tb->empty() || tw->empty()) return std::nullopt;
  const AlignedTruth tbody = align_truth(*tb, body.time()), twheels = align_truth(*tw, wheels.time());
  std::vector<char> mask = moving_samples(wheels, "valid", tbody, "velocity_x", "velocity_y", 1e-3);
  const std::vector<double>& t = wheels.time();
  std::size_t with_truth = 0;
  for (std::size_t i = 0; i < mask.size(); ++i) {
    if (within_span(*tb, t[i]) && within_span(*tw, t[i])) {
      ++with_truth;
    } else {
      mask[i] = 0;
    }
  }
  if (with_truth == 0) return std::nullopt;
  estimation::StateErrors e;
  e.samples = static_cast<std::size_t>(std::count(mask.begin(), mask.end(), 1));
  for (const char* c : {"velocity_x", "velocity_y", "velocity_z"})
    e.velocity.push_back(rms_error(body, c, tbody, c, mask, e.samples));
  // The wheels' channels in the estimate's order: slip_<wheel>, then the angles.
  for (const auto& ch : wheels.channels()) {
    const std::string& c = ch.name;
    auto rms = [&]() { return rms_error(wheels, c, twheels, c, mask, e.samples); };
    if (c.rfind("slip_", 0) == 0) e.slip.push_back(rms());
    if (c.rfind("contact_angle_", 0) == 0) e.contact_angle.push_back(rms());
    if (c.rfind("side_slip_", 0) == 0) e.side_slip.push_back(rms());
  }
  return e;
}

}  // namespace roverlab::analysis
