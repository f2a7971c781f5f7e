// `roverlab render`: one view of a log as a PNG, headless.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "app/analysis.h"
#include "app/command.h"
#include "app/command_support.h"
#include "app/commands.h"
#include "app/render_view.h"
#include "app/views_input.h"
#include "core/common/error.h"
#include "views/view.h"
#include "views/x_display.h"

namespace roverlab::app {

namespace {

namespace fs = std::filesystem;

struct RenderOptions {
  std::string file;
  std::optional<std::string> mapping;
  std::string view = views::all_views().front()->name();
  std::optional<double> time;
  std::optional<std::string> channels;
  std::optional<std::string> x_channel, y_channel;
  std::optional<std::string> soil;
  std::string quantity = "drawbar-pull";
  std::optional<double> slip_angle_deg;
  std::string size = "1280x800";
  std::string output;
  std::vector<std::string> compare;  // other runs, for the views that compare_runs()
};

// The names of the views for which `uses` holds, e.g. "a | b".
std::string views_that(bool (views::View::*uses)() const) {
  std::string out;
  for (const auto& v : views::all_views()) {
    if (((*v).*uses)()) out += (out.empty() ? "" : " | ") + v->name();
  }
  return out;
}

// The analyses that add a stream `view` draws (one's name prefix starts the other's).
std::vector<std::string> analyses_drawn_by(const views::View& view) {
  const std::vector<std::string> drawn = view.estimates_drawn();
  return all_analysis_names([&](const Analysis& a) {
    for (const std::string& added : a.identity().estimate_streams) {
      for (const std::string& d : drawn) {
        if (added.rfind(d, 0) == 0 || d.rfind(added, 0) == 0) return true;
      }
    }
    return false;
  });
}

int run_render(const RenderOptions& o) {
  const auto [w, h] = parse_size(o.size);
  const views::View* view = views::find_view(o.view);
  if (view == nullptr) throw UsageError("--view " + o.view + ": expected " + views::view_names());
  if ((o.x_channel || o.y_channel) && !view->plots_channel_pair())
    throw UsageError(std::string(o.x_channel ? "--x" : "--y") + ": only for the " +
                     views_that(&views::View::plots_channel_pair) + " view");
  if (fs::path(o.output).extension() != ".png") throw UsageError("--output " + o.output + ": must end in .png");
  ViewInputOptions vo;
  vo.analyses = analyses_drawn_by(*view);    // the estimators whose streams it draws, no study it does not
  if (view->uses_surface_data() && !o.soil)  // a rover's own surfaces
    vo.analyses = all_analysis_names([](const Analysis& a) { return a.presentation().draws_traction_surfaces(); });
  // Refused before any analysis runs: a time outside the log.
  vo.check_log = [&o, view](const log::Log& lg) {
    check_time_in_log(lg, o.time);
    if (const std::string lacks = view->needs_before_estimates(lg); !lacks.empty()) throw InputError(o.file, lacks);
  };
  if (!o.compare.empty() && !view->compares_runs())
    throw UsageError("--compare: only for the " + views_that(&views::View::compares_runs) + " view");
  const ViewInput in = load_view_input(o.file, o.mapping, vo);
  std::vector<ViewInput> others;  // the measured streams only: no analysis runs on them
  for (const std::string& f : o.compare) others.push_back(load_view_input(f, o.mapping));
  ViewOptions options;
  options.time = o.time;
  options.channel_spec = o.channels;
  options.x_channel = o.x_channel;
  options.y_channel = o.y_channel;
  options.soil = o.soil;
  options.quantity = o.quantity;
  options.slip_angle_deg = o.slip_angle_deg;
  // What the view needs is checked before the display server starts.
  for (const ViewInput& other : others) options.compared.emplace_back(fs::path(other.file).stem().string(), &other.log);
  const views::SceneInput input = scene_input(in, *view, options);
  views::ensure_display();
  const Rendered r = render_view(*view, input, w, h);
  save_png(r.image, o.output);
  for (const auto& n : in.notes) std::printf("note: %s\n", n.c_str());
  for (const auto& n : r.notes) std::printf("note: %s\n", n.c_str());
  char when[48] = "";
  if (std::isfinite(r.time)) std::snprintf(when, sizeof when, ", t = %.2f s", r.time);
  std::printf("wrote %s (%dx%d, %s view%s)\n", o.output.c_str(), w, h, o.view.c_str(), when);
  return kSuccess;
}

}  // namespace

Commands make_render_commands() {
  Commands commands;
  commands.push_back(make_command<RenderOptions>(
      "render", "Render one view of a log to PNG, headless (starts a private Xvfb when DISPLAY is unset)",
      [](CLI::App& cmd, RenderOptions& o) {
        cmd.add_option("FILE", o.file, "Log (HDF5, .mat with --mapping, CSV) or single-wheel CSV")->required();
        cmd.add_option("--mapping,-m", o.mapping, "Mapping NAME or FILE for .mat/HDF5 input");
        cmd.add_option("--view", o.view, views::view_names(" | ", " | "))->capture_default_str();
        cmd.add_option("--time,-t", o.time, "Time shown, s (default: mid-log)")->check(finite_in(-1e12, 1e12));
        const std::string plots = views_that(&views::View::uses_channels);
        const std::string surfaces = views_that(&views::View::uses_surface_data);
        cmd.add_option("--channels", o.channels, plots + ": stream:channel,... (a stream alone: all its channels)");
        const std::string pairs = views_that(&views::View::plots_channel_pair);
        cmd.add_option("--x", o.x_channel, pairs + ": the horizontal axis's STREAM:CHANNEL");
        cmd.add_option("--y", o.y_channel, pairs + ": the vertical axis's STREAM:CHANNEL");
        cmd.add_option("--soil", o.soil, surfaces + ": draw the Wong-Reece model surface of soil NAME|FILE");
        cmd.add_option("--quantity", o.quantity, surfaces + ": drawbar-pull | torque | lateral-force")
            ->capture_default_str()
            ->check(CLI::IsMember({"drawbar-pull", "torque", "lateral-force"}));
        cmd.add_option("--slip-angle", o.slip_angle_deg,
                       surfaces +
                           ": slip angle, deg (lateral-force default: the largest in the file, else 10; "
                           "drawbar-pull, torque: the file's nearest 0)")
            ->check(finite_in(-90.0, 90.0));
        cmd.add_option(
            "--compare", o.compare,
            views_that(&views::View::compares_runs) +
                ": another run (log) drawn against FILE, aligned by the clocks as recorded; repeatable (--channels: "
                "those drawn, default: those that differ most)");
        cmd.add_option("--size", o.size, "WxH pixels")->capture_default_str();
        cmd.add_option("--output,-o", o.output, "OUT.png")->required();
      },
      run_render));
  return commands;
}

}  // namespace roverlab::app
