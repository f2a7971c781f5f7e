#include "app/compare_document.h"

#include <cmath>

namespace roverlab::app {

namespace {

using nlohmann::json;

json number(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

}  // namespace

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
          {"bias", number(c.bias)},
          {"rms_difference", number(c.rms)},
          {"baseline_sigma", number(c.base_sigma)},
          {"run_sigma", number(c.other_sigma)},
          {"sigma_source", c.logged_sigma ? "logged" : "estimated"},
          {"beyond_noise", number(c.beyond_noise)},
          {"blocks", c.test.blocks},
          {"statistic", number(c.test.statistic)},
          {"threshold", number(c.test.threshold)},
          {"p_value", number(c.test.p_value)},
          {"oscillation",
           {{"segments", c.oscillation.segments},
            {"statistic", number(c.oscillation.statistic)},
            {"threshold", number(c.oscillation.threshold)},
            {"p_value", number(c.oscillation.p_value)},
            {"cycles_per_sample", number(c.oscillation.peak_cycles_per_sample)},
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
