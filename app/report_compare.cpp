#include "app/report_compare.h"
#include "core/log/conventions.h"

#include <algorithm>
#include <cmath>

#include "app/command_support.h"
#include "app/compare_document.h"
#include "app/report_plot.h"
#include "core/comparison/compare.h"

namespace roverlab::app {

namespace {

using nlohmann::json;

constexpr std::size_t kMaxPoints = 1500;  // a drawn curve, at most
constexpr std::size_t kMaxOverlays = 4;   // channels drawn per run
const char* const kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};

const char* colour(std::size_t k) { return kColours[k % (sizeof kColours / sizeof kColours[0])]; }

// Every n-th value, so that at most kMaxPoints remain.
std::vector<double> thinned(const std::vector<double>& v) {
  const std::size_t stride = std::max<std::size_t>(1, (v.size() + kMaxPoints - 1) / kMaxPoints);
  std::vector<double> out;
  for (std::size_t k = 0; k < v.size(); k += stride) out.push_back(v[k]);
  return out;
}

// The channels drawn: those that differ, most significant first, then the
// largest test statistics.
std::vector<const comparison::ChannelComparison*> drawn_channels(const comparison::RunComparison& r) {
  std::vector<const comparison::ChannelComparison*> order;
  for (const auto& c : r.channels) order.push_back(&c);
  std::stable_sort(order.begin(), order.end(), [](const auto* a, const auto* b) {
    if (a->differs != b->differs) return a->differs;
    return a->test.statistic > b->test.statistic;
  });
  if (order.size() > kMaxOverlays) order.resize(kMaxOverlays);
  return order;
}

// One channel of both runs over each other, and their difference below.
json overlay(std::ostringstream& html, const log::Log& base, const comparison::RunComparison& r,
             const comparison::ChannelComparison& c, const std::string& prefix) {
  const log::Stream& d = r.differences.stream(prefix + "/" + c.stream);
  const std::vector<double>& time = d.time();
  const std::vector<double> baseline = base.stream(c.stream).interpolate(c.channel, time);
  const std::vector<double>& difference = d.channel(c.channel).values;
  std::vector<double> run(time.size());
  for (std::size_t k = 0; k < time.size(); ++k) run[k] = baseline[k] + difference[k];
  json drawn = {{"channel", c.path()},
                {"time", thinned(time)},
                {"baseline", thinned(baseline)},
                {"run", thinned(run)},
                {"difference", thinned(difference)}};
  PlotSeries a("baseline", colour(0), drawn["baseline"].get<std::vector<double>>());
  PlotSeries b("run", colour(1), drawn["run"].get<std::vector<double>>());
  PlotSeries diff("run - baseline", "#333", drawn["difference"].get<std::vector<double>>());
  a.x = b.x = diff.x = drawn["time"].get<std::vector<double>>();
  // The +-2 sigma band of the two streams' noise the difference would stay in without one.
  const double band = 2.0 * std::hypot(c.base_sigma, c.other_sigma);
  drawn["noise_band"] = band;
  const std::vector<double> ends = {diff.x.empty() ? 0.0 : diff.x.front(), diff.x.empty() ? 0.0 : diff.x.back()};
  PlotSeries noise("+-2 sigma noise", "#999", {band, band, NAN, -band, -band});  // NaN: two lines
  noise.x = {ends[0], ends[1], ends[1], ends[0], ends[1]};
  const std::string unit = " (" + c.unit + ")";
  PlotSpec values(c.path(), "baseline time (s)", c.channel + unit, {a, b});
  PlotSpec below(c.path() + ": difference" + (c.differs ? " (differs)" : " (within noise)"), "baseline time (s)",
                 "difference" + unit, {diff});
  if (std::isfinite(band)) below.series.insert(below.series.begin(), noise);
  values.css_class = below.css_class = "plot compare";
  html << "<div class=\"overlay\">" << plot_svg(values) << "<br>" << plot_svg(below) << "</div>\n";
  return drawn;
}

// Every run's track on one map.
json track_map(std::ostringstream& html, const std::string& base_file, const log::Log& base,
               const std::vector<ComparedLog>& runs) {
  json tracks = json::array();
  std::vector<PlotSeries> series;
  std::string x_title, y_title;
  for (std::size_t k = 0; k <= runs.size(); ++k) {
    const log::Log& lg = k == 0 ? base : runs[k - 1].log;
    const comparison::PositionTrack p = comparison::position_track(lg);
    if (p.stream.empty()) continue;
    const log::Stream& s = lg.stream(p.stream);
    PlotSeries line(k == 0 ? "baseline (dots)" : "run " + std::to_string(k + 1), colour(k),
                    thinned(s.channel(p.y).values));
    line.x = thinned(s.channel(p.x).values);
    line.points = k == 0;  // a run on the same path hides the baseline's line, not its dots
    tracks.push_back({{"file", k == 0 ? base_file : runs[k - 1].file},
                      {"stream", p.stream},
                      {"x_channel", p.x},
                      {"y_channel", p.y},
                      {"x", line.x},
                      {"y", line.y}});
    x_title = p.stream + " " + p.x + " (m)";
    y_title = p.stream + " " + p.y + " (m)";
    series.push_back(std::move(line));
  }
  if (!series.empty()) {
    PlotSpec map("Every run's track", x_title, y_title, std::move(series));
    map.css_class = "plot compare-map";
    html << plot_svg(map) << "\n";
  }
  return tracks;
}

void run_section(std::ostringstream& html, const std::string& file, std::size_t index,
                 const comparison::RunComparison& r) {
  html << "<h3>Run " << index << ": " << ReportSection::escape(file) << "</h3>\n<p>Aligned by "
       << ReportSection::escape(r.alignment.how);
  if (r.alignment.by != comparison::AlignBy::distance) {
    html << ", offset " << ReportSection::number(r.alignment.offset_s, "%+.4f") << " s";
  }
  html << ". " << r.differing() << " of " << r.channels.size()
       << " shared channels differ beyond noise (false-alarm rate " << ReportSection::number(r.false_alarm, "%.3g")
       << " per channel)";
  if (r.differing() > 0) {
    html << ":";
    for (const auto& c : r.channels) {
      if (c.differs) html << " " << ReportSection::escape(c.path());
    }
  }
  html << ".</p>\n";
  if (!r.only_in_base.empty())
    html << "<p class=\"note\">Only in the baseline: " << r.only_in_base.size() << " channels.</p>\n";
  if (!r.only_in_other.empty())
    html << "<p class=\"note\">Only in this run: " << r.only_in_other.size() << " channels.</p>\n";
}

}  // namespace

void write_comparison_section(ReportSection& section, json& metrics, const std::string& base_file,
                              const log::Log& with_estimates, const std::vector<ComparedLog>& runs) {
  // The measured streams: the report's own analyses' estimates (estimate/) are not in the other runs.
  log::Log base;
  base.metadata = with_estimates.metadata;
  for (const auto& s : with_estimates.streams()) {
    if (s.name().rfind(log::kEstimatePrefix, 0) != 0) base.add_stream(s);
  }
  std::ostringstream& html = section.html;
  html << "<h2>Comparison with other runs</h2>\n<p>The baseline is this report's log; each run is aligned to it and "
          "every measured channel both have (not this report's estimates) is tested for a difference beyond the two "
          "runs' "
          "noise (docs/compare.md).</p>\n";
  json doc = {{"baseline", base_file}, {"runs", json::array()}, {"overlays", json::array()}};
  doc["map"] = track_map(html, base_file, base, runs);
  comparison::CompareOptions options;
  options.keep_differences = true;
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const comparison::RunComparison r =
        about_file(runs[k].file, [&] { return comparison::compare_runs(base, runs[k].log, options); });
    run_section(html, runs[k].file, k + 2, r);
    doc["runs"].push_back(comparison_json(runs[k].file, r));
    for (const auto* c : drawn_channels(r)) {
      json drawn = overlay(html, base, r, *c, options.difference_prefix);
      drawn["file"] = runs[k].file;
      doc["overlays"].push_back(std::move(drawn));
    }
  }
  metrics["comparison"] = std::move(doc);
}

}  // namespace roverlab::app
