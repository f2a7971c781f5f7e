#pragma once
// A model family evaluated where a view or a surface fit needs it: one
// curve over slip at a given load and slip angle, and the load x slip grid a
// polynomial surface is fitted to (seed 003 Appendix A). One evaluator for
// every caller (the `terramechanics surface` command, the traction-surface
// view, the per-angle views), so they agree point for point.

#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "core/terramechanics/slip_angle_model.h"
#include "core/terramechanics/traction_surface.h"

namespace roverlab::terramechanics {

// The model evaluated: a soil, a wheel, the family and its extensions
// (ModelOptions::kind: wong_reece, ishigami or rft), and the lateral options.
struct GridModel {
  Soil soil;
  Wheel wheel;
  ModelOptions options;
  LateralOptions lateral;
};

// The traction at load W (N), slip s and slip angle beta (rad): at no slip
// angle (nullopt) the longitudinal model (model.h: evaluate), else the
// slip-angle model (slip_angle_model.h; RFT when options.kind is rft).
SlipAngleTraction model_at(const GridModel& model, double load, double slip, std::optional<double> slip_angle);

// `points` evenly spaced slips from slip_min to slip_max (both included) at
// one load and slip angle; a slip the model cannot carry has status != ok.
struct ModelCurve {
  std::vector<double> slip;
  std::vector<SlipAngleTraction> traction;
};
ModelCurve model_curve(const GridModel& model, double load, std::optional<double> slip_angle, double slip_min,
                       double slip_max, int points);

// The load x slip grid: `loads` x `slips` evenly spaced nodes over the
// ranges (each axis with at least 2 nodes), load outer, slip inner.
struct GridRange {
  double load_min = 10.0, load_max = 200.0;
  double slip_min = 0.0, slip_max = 1.0;
  int loads = 40, slips = 40;
};

// The model's samples on the grid, the nodes it cannot carry left out and counted.
struct ModelGrid {
  std::vector<SurfaceSample> drawbar_pull, resistive_torque, lateral_force;
  std::size_t unsupported = 0;
};

// `row_done(i, loads)` is called after each load row (progress; may be empty).
ModelGrid model_grid(const GridModel& model, const GridRange& range, std::optional<double> slip_angle,
                     const std::function<void(int, int)>& row_done = {});

}  // namespace roverlab::terramechanics
