#include "app/compare_document.h"

#include <cmath>

#include "app/analysis.h"

namespace roverlab::app {

using nlohmann::json;

const char* alignment_name(comparison::AlignBy by) {
  switch (by) {
    case comparison::AlignBy::time:
      return "time";
    case comparison::AlignBy::motion:
      return "motion";
    case comparison::AlignBy::distance:
      return "distance";
  }
  return "time";
}

namespace {

json alignment_json(const comparison::Alignment& a) {
  json j = {{"by", alignment_name(a.by)}, {"how", a.how}};
  if (a.by != comparison::AlignBy::distance) j["offset_s"] = a.offset_s;
  if (std::isfinite(a.correlation)) j["correlation"] = a.correlation;
  if (a.by == comparison::AlignBy::motion) {
    j["baseline_start_s"] = a.base_event_s;
    j["run_start_s"] = a.other_event_s;
  }
  if (!a.position_source.empty()) j["position_source"] = a.position_source;
  return j;
}

json channel_json(const comparison::ChannelComparison& c) {
  return {{"stream", c.stream},
          {"channel", c.channel},
          {"unit", c.unit},
          {"samples", c.samples},
          {"bias", finite_or_null(c.bias)},
          {"rms_difference", finite_or_null(c.rms)},
          {"baseline_sigma", finite_or_null(c.base_sigma)},
          {"run_sigma", finite_or_null(c.other_sigma)},
          {"sigma_source", c.logged_sigma ? "logged" : "estimated"},
          {"beyond_noise", finite_or_null(c.beyond_noise)},
          {"blocks", c.test.blocks},
          {"statistic", finite_or_null(c.test.statistic)},
          {"threshold", finite_or_null(c.test.threshold)},
          {"p_value", finite_or_null(c.test.p_value)},
          {"oscillation",
           {{"segments", c.oscillation.segments},
            {"statistic", finite_or_null(c.oscillation.statistic)},
            {"threshold", finite_or_null(c.oscillation.threshold)},
            {"p_value", finite_or_null(c.oscillation.p_value)},
            {"cycles_per_sample", finite_or_null(c.oscillation.peak_cycles_per_sample)},
            {"differs", c.oscillation.differs}}},
          {"differs", c.differs}};
}

}  // namespace

json comparison_json(const std::string& file, const comparison::RunComparison& r) {
  json j = {{"file", file},
            {"alignment", alignment_json(r.alignment)},
            {"channels", json::array()},
            {"differing", json::array()},
            {"only_in_baseline", r.only_in_base},
            {"only_in_run", r.only_in_other},
            {"not_compared", r.not_compared}};
  for (const auto& c : r.channels) {
    j["channels"].push_back(channel_json(c));
    if (c.differs) j["differing"].push_back(c.path());
  }
  return j;
}

}  // namespace roverlab::app
