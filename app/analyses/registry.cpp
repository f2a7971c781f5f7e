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
