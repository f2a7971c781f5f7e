// View speed (issue 7 target: at least 30 frames per second): the rover view's
// frame time on the bundled log, and a time-series redraw (re-decimate and
// render) of a ten-million-sample channel, offscreen at 1280x800 (under Xvfb
// this is software rendering; a private Xvfb starts when DISPLAY is unset).
#include <benchmark/benchmark.h>

#include <vtkContextView.h>
#include <vtkOpenGLRenderWindow.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>

#include <cmath>
#include <string>

#include "core/estimation/ins_slip/ins_slip.h"
#include "importers/log_file.h"
#include "importers/mapping.h"
#include "views/offscreen.h"
#include "views/rover_scene.h"
#include "views/timeseries_chart.h"
#include "views/x_display.h"

namespace {

using namespace roverlab;

const log::Log& pathfinder_with_estimates() {
  static const log::Log lg = [] {
    const std::string root = ROVERLAB_SOURCE_DIR;
    io::LoadOptions o;
    o.mapping = io::load_mapping(root + "/resources/mappings/wvu_pathfinder.json");
    log::Log l = io::load_log(root + "/tests/data/test17run.mat", o).log;
    const auto r = estimation::run_ins_slip(l, {});
    for (const auto& s : r.estimates.streams()) l.add_stream(s);
    return l;
  }();
  return lg;
}

void finish(vtkRenderWindow* w) {
  if (auto* gl = vtkOpenGLRenderWindow::SafeDownCast(w)) gl->WaitForCompletion();
}

void BM_RoverViewFrame(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0)), height = static_cast<int>(state.range(1));
  views::RoverScene scene(pathfinder_with_estimates());
  auto window = views::make_offscreen_window(width, height);
  window->AddRenderer(scene.renderer());
  double t = scene.start_time();
  for (auto _ : state) {
    t += 0.1;
    if (t > scene.end_time()) t = scene.start_time();
    scene.set_time(t);
    window->Render();
    finish(window);
  }
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RoverViewFrame)->Args({1280, 800})->Args({640, 400})->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_PlotRedrawTenMillionSamples(benchmark::State& state) {
  const std::size_t n = 10'000'000;
  std::vector<double> t(n), v(n);
  for (std::size_t i = 0; i < n; ++i) {
    t[i] = 1e-4 * static_cast<double>(i);  // 1000 s at 10 kHz
    v[i] = std::sin(0.05 * t[i]) + 0.1 * std::sin(37.0 * t[i]);
  }
  log::Log lg;
  log::Stream s("signal", std::move(t));
  s.add_channel("x", "1", std::move(v));
  lg.add_stream(std::move(s));
  views::TimeSeriesChart chart(lg, {{"signal", "x"}});
  auto window = views::make_offscreen_window(1280, 800);
  chart.view()->SetRenderWindow(window);
  int k = 0;
  for (auto _ : state) {
    // Zoom and pan: a window of 10..1000 s at a moving start, re-decimated.
    const double span = 10.0 * std::pow(10.0, (k % 3));
    const double start = std::fmod(37.0 * k, 1000.0 - span);
    chart.set_window(start, start + span, 1280);
    chart.set_cursor(start + 0.5 * span);
    window->Render();
    finish(window);
    ++k;
  }
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PlotRedrawTenMillionSamples)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

int main(int argc, char** argv) {
  roverlab::views::ensure_display();
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
