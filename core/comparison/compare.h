#pragma once
// Two runs side by side (issue 45): the other run aligned to the baseline,
// both resampled onto the baseline's time base stream by stream, and for
// each channel both have: bias, RMS difference, the part of it beyond the
// two streams' noise, and whether it differs (difference_test.h for a bias
// or drift, oscillation_test.h for a periodic part, Bonferroni) at a
// stated false-alarm rate. Channels only one run has are listed.

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "core/comparison/alignment.h"
#include "core/comparison/difference_test.h"
#include "core/comparison/oscillation_test.h"
#include "core/log/log.h"

namespace roverlab::comparison {

struct CompareOptions {
  AlignmentOptions alignment;
  double false_alarm = 0.01;  // per channel
  std::size_t blocks = 20;    // of the F test
  bool keep_differences = false;
  std::string difference_prefix = "difference";  // streams <prefix>/<stream> of the kept differences
};

struct ChannelComparison {
  std::string stream, channel, unit;
  std::size_t samples = 0;                     // baseline times where both runs have a value
  double bias = NAN;                           // mean of other - base
  double rms = NAN;                            // RMS of other - base
  double base_sigma = NAN, other_sigma = NAN;  // each stream's noise
  bool logged_sigma = false;                   // from a <channel>_sigma channel rather than estimated
  // sqrt(max(0, rms^2 - noise^2)): noise^2 is base_sigma^2 + other_sigma^2, each times the share of a white
  // noise's variance its interpolation onto the common times keeps (1 at a sample, 1/2 halfway)
  double beyond_noise = NAN;
  DifferenceTest test;          // the block F test of a bias or drift, at half the false-alarm rate
  OscillationTest oscillation;  // the periodogram test of a periodic part, at the other half
  bool differs = false;         // either test; false when rms is below 1e-9 of the baseline's RMS (rounding)
  std::string path() const { return stream + "/" + channel; }
};

struct RunComparison {
  Alignment alignment;
  double false_alarm = 0.01;
  std::vector<ChannelComparison> channels;               // shared channels, in the baseline's order
  std::vector<std::string> only_in_base, only_in_other;  // "stream/channel"
  std::vector<std::string> not_compared;                 // shared streams or channels that cannot be compared, with why
  log::Log differences;  // <prefix>/<stream>: other - base on the baseline's times (keep_differences)
  std::size_t differing() const;
};

// Throws DataError for what the alignment cannot use (see align_runs).
RunComparison compare_runs(const log::Log& base, const log::Log& other, const CompareOptions& options);

}  // namespace roverlab::comparison
