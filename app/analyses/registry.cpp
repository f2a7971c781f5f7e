// The analysis registry (app/analyses/analyses.def) and the report helpers.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include <elf.h>
#include <link.h>

#include "app/analysis.h"
#include "app/command_support.h"
#include "core/log/conventions.h"
#include "importers/atomic_file.h"
#include "importers/json_resource.h"

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

namespace {

// FNV-1a over bytes, continued from `h`.
std::uint64_t fnv1a(const void* data, std::size_t n, std::uint64_t h) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t k = 0; k < n; ++k) h = (h ^ p[k]) * 1099511628211ULL;
  return h;
}

std::uint64_t fnv1a(const std::string& s, std::uint64_t h) { return fnv1a(s.data(), s.size() + 1, h); }

// The GNU build id of the main program's ELF notes, in hex; empty when it has none.
int read_build_id(dl_phdr_info* info, std::size_t, void* out) {
  auto& id = *static_cast<std::string*>(out);
  for (int i = 0; i < info->dlpi_phnum; ++i) {
    const ElfW(Phdr)& ph = info->dlpi_phdr[i];
    if (ph.p_type != PT_NOTE) continue;
    // The loader gives the note's place as an address.
    // NOLINTNEXTLINE(performance-no-int-to-ptr)
    const char* p = reinterpret_cast<const char*>(info->dlpi_addr + ph.p_vaddr);
    const char* end = p + ph.p_memsz;
    while (p + sizeof(ElfW(Nhdr)) <= end) {
      ElfW(Nhdr) n;
      std::memcpy(&n, p, sizeof n);
      const char* name = p + sizeof n;
      const char* desc = name + ((n.n_namesz + 3U) & ~3U);
      if (desc + n.n_descsz > end) break;
      if (n.n_type == NT_GNU_BUILD_ID && n.n_namesz == 4 && std::memcmp(name, "GNU", 4) == 0) {
        for (std::size_t k = 0; k < n.n_descsz; ++k) {
          char hex[3];
          std::snprintf(hex, sizeof hex, "%02x", static_cast<unsigned char>(desc[k]));
          id += hex;
        }
        return 1;
      }
      p = desc + ((n.n_descsz + 3U) & ~3U);
    }
  }
  return 1;  // the first object is the main program: stop there
}

}  // namespace

std::string program_identity() {
  static const std::string id = [] {
    std::string build;
    dl_iterate_phdr(read_build_id, &build);
#ifdef ROVERLAB_VERSION
    const std::string version = ROVERLAB_VERSION;
#else
    const std::string version = "unknown";
#endif
    return build.empty() ? version : version + "+" + build;
  }();
  return id;
}

std::string log_fingerprint(const log::Log& lg) {
  std::uint64_t h = fnv1a(lg.metadata.rover_id, 14695981039346656037ULL);
  // The metadata an analysis reads: the scenario a simulated log records (the rover study models it).
  for (const char* key : {"scenario", "scenario_json"}) {
    const auto it = lg.metadata.extra.find(key);
    h = fnv1a(it == lg.metadata.extra.end() ? std::string(1, '\0') : key + ("=" + it->second), h);
  }
  for (const auto& s : lg.streams()) {
    if (s.name().rfind(log::kEstimatePrefix, 0) == 0) continue;  // what analyses add, not what was measured
    h = fnv1a(s.name(), h);
    h = fnv1a(s.time().data(), s.time().size() * sizeof(double), h);
    for (const auto& c : s.channels()) {
      h = fnv1a(c.name, h);
      h = fnv1a(c.unit, h);
      h = fnv1a(c.values.data(), c.values.size() * sizeof(double), h);
    }
  }
  char text[24];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
  return text;
}

AnalysisResult run_analysis(Analysis& analysis, const AnalysisInput& input) {
  AnalysisResult r = about_file(input.file, [&] { return analysis.run(input); });
  r.document["configuration"] = analysis.configuration();
  r.document["input"] = {
      {"fingerprint", log_fingerprint(input.log)},
      {"program", program_identity()},
      {"settings", about_file(input.file, [&] { return analysis.resolved_configuration(input.log); })}};
  return r;
}

namespace {

// The stored document is of the shape its analysis reads: its text, summary,
// tables and key metrics are made from it without a type error (a field of
// another type, fingerprint intact, would otherwise end as an internal error).
bool readable_result(const Analysis& analysis, const nlohmann::json& doc) {
  try {
    char* buffer = nullptr;
    std::size_t size = 0;
    std::FILE* out = open_memstream(&buffer, &size);
    if (out == nullptr) return false;
    try {
      analysis.presentation().print(doc, out);
    } catch (...) {
      std::fclose(out);
      std::free(buffer);
      throw;
    }
    std::fclose(out);
    std::free(buffer);
    const Presentation& shown = analysis.presentation();
    (void)shown.summary(doc);
    (void)shown.tables(doc);
    for (const KeyMetric& m : shown.key_metrics()) (void)key_metric_value(doc, m);
    return true;
  } catch (const nlohmann::json::exception&) {
    return false;
  } catch (const std::invalid_argument&) {
    return false;
  }
}

}  // namespace

std::optional<nlohmann::json> stored_result(const Analysis& analysis, const log::Log& lg,
                                            const std::function<std::string()>& fingerprint) {
  const auto at = lg.metadata.results.find(analysis.name());
  if (at == lg.metadata.results.end()) return std::nullopt;
  // Nested deeper than any result is (a copy of it would overflow the stack): run again.
  nlohmann::json doc = io::parse_bounded_json(at->second);
  if (!doc.is_object() || !doc.contains("input") || !doc.at("input").is_object()) return std::nullopt;
  const nlohmann::json& input = doc.at("input");
  if (input.value("program", std::string()) != program_identity()) return std::nullopt;
  nlohmann::json settings;
  try {
    settings = analysis.resolved_configuration(lg);
  } catch (const std::exception&) {
    return std::nullopt;  // running it says what is wrong
  }
  if (input.value("settings", nlohmann::json()) != settings ||
      input.value("fingerprint", std::string()) != (fingerprint ? fingerprint() : log_fingerprint(lg))) {
    return std::nullopt;
  }
  if (!readable_result(analysis, doc)) return std::nullopt;
  return doc;
}

void store_result(const Analysis& analysis, const nlohmann::json& document, log::Log& estimates) {
  estimates.metadata.results[analysis.name()] = document.dump();
}

nlohmann::json without_run_details(nlohmann::json document) {
  if (!document.is_object()) return document;
  for (const char* key : {"wall_seconds", "output", "program"}) document.erase(key);
  for (auto& [key, value] : document.items()) {
    if (value.is_object()) value = without_run_details(std::move(value));
  }
  return document;
}

std::string configuration_text(const nlohmann::json& document) {
  if (!document.is_object() || !document.contains("configuration") || !document.at("configuration").is_object())
    return {};
  std::string text;
  for (const auto& [key, value] : document.at("configuration").items()) {
    std::string shown = value.is_string() ? value.get<std::string>() : value.is_null() ? "default" : value.dump();
    text += (text.empty() ? "settings: " : ", ") + key + " " + shown;
  }
  return text.empty() ? text : text + "\n";
}

std::string printed(const Analysis& analysis, const nlohmann::json& document) {
  char* buffer = nullptr;
  std::size_t size = 0;
  std::FILE* out = open_memstream(&buffer, &size);
  if (out == nullptr) return {};
  analysis.presentation().print(document, out);
  std::fputs(configuration_text(document).c_str(), out);
  std::fclose(out);
  std::string text(buffer, size);
  std::free(buffer);
  return text;
}

nlohmann::json key_metric_value(const nlohmann::json& doc, const KeyMetric& m) {
  const nlohmann::json::json_pointer ptr(m.pointer);
  if (!doc.is_object() || !doc.contains(ptr)) return nullptr;
  const nlohmann::json& v = doc.at(ptr);
  if (m.verdict) return v.is_string() ? v : nlohmann::json(nullptr);
  if (v.is_number()) return v;
  if (v.is_array() && !v.empty()) {  // per wheel: the mean
    double sum = 0;
    for (const auto& x : v) {
      if (!x.is_number()) return nullptr;
      sum += x.get<double>();
    }
    return sum / static_cast<double>(v.size());
  }
  return nullptr;
}

std::string Presentation::summary(const nlohmann::json& document) const {
  std::string out;
  for (const KeyMetric& m : key_metrics()) {
    const nlohmann::json v = key_metric_value(document, m);
    if (v.is_null()) continue;
    const std::string text = v.is_string() ? v.get<std::string>() : ReportSection::number(v.get<double>(), "%.4g");
    out += (out.empty() ? "" : "; ") + m.title + " " + text;
  }
  return out.empty() ? out : out + ".";
}

void ReportSection::write_csv(const std::string& name, const std::string& text) const {
  io::write_text_atomically((folder_ / name).string(), text);
  wrote(name);
}

namespace {

// A number as the tables write one ("0.9981+-0.0012", "< -1e6", "1,234", "43.2 %", an en dash).
bool numeric_text(const std::string& text) {
  if (text.empty()) return false;
  return std::all_of(text.begin(), text.end(), [](char c) {
    return std::isdigit(static_cast<unsigned char>(c)) || std::strchr(".,+-eE<> %~", c) != nullptr ||
           (static_cast<unsigned char>(c) & 0x80) != 0;
  });
}

}  // namespace

void ReportSection::table(const ResultTable& t) {
  html << "<table class=\"result\"><caption>" << escape(t.title) << "</caption>\n<tr>";
  if (!t.row_names.empty()) html << "<th></th>";
  for (const auto& c : t.columns) html << "<th>" << escape(c) << "</th>";
  html << "</tr>\n";
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    const auto& row = t.rows[i];
    const bool bold = !row.empty() && std::all_of(row.begin(), row.end(), [](const auto& c) { return c.bold; });
    html << (bold ? "<tr style=\"font-weight:bold\">" : "<tr>");
    if (!t.row_names.empty()) html << "<th>" << escape(i < t.row_names.size() ? t.row_names[i] : "") << "</th>";
    for (const auto& cell : row) {
      std::string style = numeric_text(cell.text) ? "white-space:nowrap;" : "text-align:left;";
      if (cell.bold && !bold) style += "font-weight:bold;";
      if (cell.shade > 0) {
        char tint[64];
        std::snprintf(tint, sizeof tint, "background:rgba(31,119,180,%.2f);", 0.6 * std::min(cell.shade, 1.0));
        style += tint;
      }
      html << (style.empty() ? "<td>" : "<td style=\"" + style + "\">") << escape(cell.text) << "</td>";
    }
    html << "</tr>\n";
  }
  html << "</table>\n";
  if (!t.legend.empty())
    html << "<p class=\"legend\" style=\"margin-top:-0.6em;font-size:90%;color:#444\">" << escape(t.legend) << "</p>\n";
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
