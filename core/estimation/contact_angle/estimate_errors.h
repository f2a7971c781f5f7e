#pragma once
// Scoring an estimator's output streams against a log's truth/ streams,
// apart from the estimators (which do not read truth). The helpers align an
// estimate stream's samples with a truth stream's by time and take the RMS
// of one channel against another over a mask, so that every estimator
// scores the same way; contact_angle_errors is the contact-angle estimator's
// scoring (seed 000 Tables 6.2-6.5 layout).

#include <cstddef>
#include <optional>
#include <string_view>
#include <vector>

#include "core/estimation/contact_angle/contact_angle.h"
#include "core/log/log.h"

namespace roverlab::analysis {

// For each estimate time, the index of the truth sample nearest in time.
struct AlignedTruth {
  const log::Stream* truth = nullptr;
  std::vector<std::size_t> index;
};
AlignedTruth align_truth(const log::Stream& truth, const std::vector<double>& estimate_time);

// The samples to compare: 1 where the estimate is valid (the estimate
// stream's `valid_channel` is non-zero; every sample when that is empty) and
// the truth's horizontal speed hypot(vx, vy) is not below min_speed.
std::vector<char> moving_samples(const log::Stream& estimate, std::string_view valid_channel, const AlignedTruth& body,
                                 std::string_view truth_vx, std::string_view truth_vy, double min_speed);

// Sum over the mask of (estimate[i] - truth_channel[index[i]])^2, in sample order.
double squared_error_sum(const std::vector<double>& estimate, const AlignedTruth& truth, std::string_view truth_channel,
                         const std::vector<char>& mask);

// sqrt(squared_error_sum / max(samples, 1)) for one estimate channel.
double rms_error(const log::Stream& estimate, std::string_view estimate_channel, const AlignedTruth& truth,
                 std::string_view truth_channel, const std::vector<char>& mask, std::size_t samples);

// The contact-angle estimator's RMS errors (velocity x y z, per wheel slip,
// contact and side-slip angle as far as its streams hold them) against
// truth/body and truth/wheels over the moving samples; nothing when the log
// has no truth. Throws DataError when a truth channel is missing.
std::optional<estimation::StateErrors> contact_angle_errors(const log::Log& log, const log::Log& estimates);

}  // namespace roverlab::analysis
