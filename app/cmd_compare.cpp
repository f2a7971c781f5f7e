// `roverlab compare A B [C ...]`: the runs after the first against the first
// (the baseline), channel by channel (core/comparison, issue 45).
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "app/command.h"
#include "app/command_support.h"
#include "app/commands.h"
#include "app/compare_document.h"
#include "app/log_input.h"
#include "core/common/error.h"
#include "core/comparison/compare.h"
#include "importers/hdf5_log.h"

namespace roverlab::app {

namespace {

using nlohmann::json;

struct CompareCommandOptions {
  std::vector<std::string> files;
  std::optional<std::string> mapping;
  std::string align = "time";
  std::optional<double> offset;
  bool find_offset = false;
  std::vector<std::string> sync;
  double max_offset = 30;
  double motion_threshold = 0.05;
  double false_alarm = 0.01;
  std::size_t blocks = 20;
  bool json = false;
  std::string output;
};

// "gps: east north up" lines from "stream/channel" paths.
std::map<std::string, std::string> by_stream(const std::vector<std::string>& paths) {
  std::map<std::string, std::string> out;
  for (const auto& p : paths) {
    const auto slash = p.rfind('/');
    std::string& line = out[p.substr(0, slash)];
    line += (line.empty() ? "" : " ") + p.substr(slash + 1);
  }
  return out;
}

void print_alignment(const comparison::Alignment& a) {
  std::printf("  aligned by %s", a.how.c_str());
  if (a.by != comparison::AlignBy::distance)
    std::printf(": offset %+.4f s (run time = baseline time + offset)", a.offset_s);
  if (std::isfinite(a.correlation)) std::printf(", peak correlation %.3f", a.correlation);
  if (a.by == comparison::AlignBy::motion) {
    std::printf(" (baseline starts at %.3f s, run at %.3f s)", a.base_event_s, a.other_event_s);
  }
  std::printf("\n");
}

void print_comparison(const std::string& file, const comparison::RunComparison& r) {
  std::printf("run       %s\n", printable(file, 1000).c_str());
  print_alignment(r.alignment);
  const std::size_t n = r.channels.size();
  std::printf(
      "  %zu shared channels compared, %zu differ beyond noise (false-alarm rate %.3g per channel: %.2g of %zu "
      "expected by chance)\n",
      n, r.differing(), r.false_alarm, r.false_alarm * static_cast<double>(n), n);
  std::printf("  %-40s %-7s %11s %11s %11s %11s %11s %8s %s\n", "channel", "unit", "bias", "rms diff", "sigma base",
              "sigma run", "beyond", "p", "differs");
  for (const auto& c : r.channels) {
    std::printf("  %-40s %-7s %11.4g %11.4g %11.4g %11.4g %11.4g %8.2g %s\n", printable(c.path()).c_str(),
                c.unit.c_str(), c.bias, c.rms, c.base_sigma, c.other_sigma, c.beyond_noise, c.test.p_value,
                c.differs ? "DIFFERS" : "no");
  }
  if (r.differing() > 0) {
    std::printf("  differ:");
    for (const auto& c : r.channels) {
      if (c.differs) std::printf(" %s", printable(c.path()).c_str());
    }
    std::printf("\n");
  }
  for (const auto& [stream, channels] : by_stream(r.only_in_base)) {
    std::printf("  only in the baseline: %s (%s)\n", printable(stream).c_str(), printable(channels, 400).c_str());
  }
  for (const auto& [stream, channels] : by_stream(r.only_in_other)) {
    std::printf("  only in this run: %s (%s)\n", printable(stream).c_str(), printable(channels, 400).c_str());
  }
  for (const auto& why : r.not_compared) std::printf("  not compared: %s\n", printable(why, 400).c_str());
}

comparison::CompareOptions core_options(const CompareCommandOptions& o) {
  comparison::CompareOptions c;
  if (o.align == "time") {
    c.alignment.by = comparison::AlignBy::time;
  } else if (o.align == "motion") {
    c.alignment.by = comparison::AlignBy::motion;
  } else if (o.align == "distance") {
    c.alignment.by = comparison::AlignBy::distance;
  } else {
    throw UsageError("--align " + o.align + ": expected time | motion | distance");
  }
  if (o.offset && o.align != "time") throw UsageError("--offset aligns by time: use it with --align time");
  if (o.offset && o.find_offset) throw UsageError("--offset and --find-offset: give the offset or find it, not both");
  c.alignment.find_offset = o.find_offset;
  c.alignment.offset_s = o.offset.value_or(0.0);
  c.alignment.sync = o.sync;
  c.alignment.max_offset_s = o.max_offset;
  c.alignment.motion_threshold_m = o.motion_threshold;
  c.false_alarm = o.false_alarm;
  c.blocks = o.blocks;
  c.keep_differences = !o.output.empty();
  return c;
}

int run_compare(const CompareCommandOptions& o) {
  if (o.files.size() < 2) throw UsageError("compare needs at least two logs: BASELINE RUN [RUN ...]");
  if (!o.output.empty()) {
    require_log_output(o.output, "--output");
    for (const auto& f : o.files) refuse_overwriting_input(f, o.output, "--output");
  }
  comparison::CompareOptions options = core_options(o);
  const io::LoadedLog base = load_input(o.files.front(), o.mapping);
  json doc = {{"baseline", o.files.front()},
              {"false_alarm_rate", o.false_alarm},
              {"blocks", o.blocks},
              {"runs", json::array()}};
  log::Log differences;
  differences.metadata.description = "differences of runs against the baseline " + o.files.front();
  differences.metadata.extra["compare/baseline"] = o.files.front();
  if (!o.json) std::printf("baseline  %s\n", printable(o.files.front(), 1000).c_str());
  for (std::size_t k = 1; k < o.files.size(); ++k) {
    const std::string& file = o.files[k];
    const io::LoadedLog other = load_input(file, o.mapping);
    options.difference_prefix = o.files.size() > 2 ? "difference/run" + std::to_string(k + 1) : "difference";
    comparison::RunComparison r =
        about_file(file, [&] { return comparison::compare_runs(base.log, other.log, options); });
    doc["runs"].push_back(comparison_json(file, r));
    if (!o.json) print_comparison(file, r);
    differences.metadata.extra["compare/" + options.difference_prefix] = file;
    for (auto& s : r.differences.streams()) differences.add_stream(s);
  }
  if (!o.output.empty()) {
    io::write_hdf5_log(differences, o.output);
    if (!o.json) std::printf("wrote %s: %zu difference streams\n", o.output.c_str(), differences.streams().size());
  }
  if (o.json) std::printf("%s\n", doc.dump(2).c_str());
  return kSuccess;
}

}  // namespace

Commands make_compare_commands() {
  Commands commands;
  commands.push_back(make_command<CompareCommandOptions>(
      "compare",
      "Runs side by side: each run against the first (the baseline), aligned; per shared channel bias, RMS "
      "difference, the part beyond noise and whether it differs (docs/compare.md)",
      [](CLI::App& cmd, CompareCommandOptions& o) {
        cmd.add_option("LOGS", o.files, "BASELINE RUN [RUN ...]")->required()->expected(2, -1);
        cmd.add_option("--mapping,-m", o.mapping, "Mapping NAME or FILE for logs that need one");
        cmd.add_option("--align", o.align, "time | motion (start of motion) | distance (travelled)")
            ->capture_default_str();
        cmd.add_option("--offset", o.offset, "s: the run's clock minus the baseline's (default 0)")
            ->check(finite_in(-1e7, 1e7));
        cmd.add_flag("--find-offset", o.find_offset,
                     "Find the time offset by cross-correlating the --sync channels (default: the clocks as recorded)");
        cmd.add_option("--sync", o.sync,
                       "stream/channel to cross-correlate (one stream; default: the fastest shared stream)");
        cmd.add_option("--max-offset", o.max_offset, "s: cross-correlation search range")
            ->capture_default_str()
            ->check(finite_in(0.01, 3600));
        cmd.add_option("--motion-threshold", o.motion_threshold, "m from the first position that starts the motion")
            ->capture_default_str()
            ->check(finite_in(1e-4, 1e3));
        cmd.add_option("--false-alarm", o.false_alarm, "per-channel false-alarm rate of 'differs'")
            ->capture_default_str()
            ->check(finite_in(1e-6, 0.5));
        cmd.add_option("--blocks", o.blocks, "blocks of the difference test")
            ->capture_default_str()
            ->check(CLI::Range(4, 1000));
        cmd.add_flag("--json", o.json, "Print JSON");
        cmd.add_option("--output,-o", o.output, "OUT.h5: a log of the difference channels (run minus baseline)");
      },
      run_compare));
  return commands;
}

}  // namespace roverlab::app
