#include "app/analyses/health.h"

namespace roverlab::app {

nlohmann::json health_json(const estimation::HealthReport& h) {
  nlohmann::json gaps = nlohmann::json::array();
  for (const estimation::TimeGap& g : h.gaps) gaps.push_back({{"start", g.start}, {"end", g.end}});
  return {{"outliers_rejected", h.outliers_rejected},
          {"missing_samples", h.missing_samples},
          {"measurements_missing", h.measurements_missing},
          {"gaps", gaps},
          {"updates", h.updates},
          {"updates_rejected", h.updates_rejected},
          {"resets", h.resets},
          {"stopped", h.stopped},
          {"invalid_fraction", h.invalid_fraction},
          {"divergence_time", finite_or_null(h.divergence_time)},
          {"nis_out_of_band_fraction", h.nis_out_of_band_fraction},
          {"status", estimation::to_string(h.status())},
          {"message", h.message()}};
}

void print_health(const nlohmann::json& document, std::FILE* out) {
  if (!document.contains("health")) return;
  const nlohmann::json& h = document.at("health");
  std::fprintf(out, "health: %s: %s\n", h.at("status").get<std::string>().c_str(),
               h.at("message").get<std::string>().c_str());
}

void report_health(const nlohmann::json& document, ReportSection& section) {
  if (!document.contains("health")) return;
  const nlohmann::json& h = document.at("health");
  section.html << "<p>Health: <b>" << ReportSection::escape(h.at("status").get<std::string>())
               << "</b>: " << ReportSection::escape(h.at("message").get<std::string>()) << ".</p>\n";
}

}  // namespace roverlab::app
