// The analysis registry (app/analyses/analyses.def) and the report helpers.
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "app/analysis.h"
#include "importers/atomic_file.h"

namespace roverlab::app {

#define ROVERLAB_ANALYSIS(name) std::unique_ptr<Analysis> make_##name##_analysis();
#include "app/analyses/analyses.def"
#undef ROVERLAB_ANALYSIS

Analyses all_analyses() {
  Analyses all;
#define ROVERLAB_ANALYSIS(name) all.push_back(make_##name##_analysis());
#include "app/analyses/analyses.def"
#undef ROVERLAB_ANALYSIS
  return all;
}

std::unique_ptr<Analysis> make_analysis(const std::string& name) {
  for (auto& a : all_analyses()) {
    if (a->name() == name) return std::move(a);
  }
  return nullptr;
}

std::string printed(const Analysis& analysis, const nlohmann::json& document) {
  char* buffer = nullptr;
  std::size_t size = 0;
  std::FILE* out = open_memstream(&buffer, &size);
  if (out == nullptr) return {};
  analysis.print(document, out);
  std::fclose(out);
  std::string text(buffer, size);
  std::free(buffer);
  return text;
}

std::string Analysis::summary(const nlohmann::json& document) const {
  std::string out;
  for (const KeyMetric& m : key_metrics()) {
    const nlohmann::json::json_pointer at(m.pointer);
    if (!document.contains(at)) continue;
    const nlohmann::json& v = document.at(at);
    std::string text;
    if (v.is_string()) {
      text = v.get<std::string>();
    } else if (v.is_number()) {
      text = ReportSection::number(v.get<double>(), "%.4g");
    } else if (v.is_array() && !v.empty()) {  // per wheel: the mean, as in the campaign table
      double sum = 0;
      std::size_t n = 0;
      for (const auto& e : v) {
        if (e.is_number()) sum += e.get<double>(), ++n;
      }
      if (n == 0) continue;
      text = ReportSection::number(sum / static_cast<double>(n), "%.4g");
    } else {
      continue;
    }
    out += (out.empty() ? "" : "; ") + m.title + " " + text;
  }
  return out.empty() ? out : out + ".";
}

void ReportSection::write_csv(const std::string& name, const std::string& text) const {
  io::write_text_atomically((folder_ / name).string(), text);
  wrote(name);
}

std::string ReportSection::escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '<') {
      o += "&lt;";
    } else if (c == '>') {
      o += "&gt;";
    } else if (c == '&') {
      o += "&amp;";
    } else {
      o += c;
    }
  }
  return o;
}

std::string ReportSection::number(double v, const char* format) {
  if (!std::isfinite(v)) return "–";
  char b[64];
  std::snprintf(b, sizeof b, format, v);
  return b;
}

std::string ReportSection::number(const nlohmann::json& v, const char* format) {
  return v.is_number() ? number(v.get<double>(), format) : "–";
}

}  // namespace roverlab::app
