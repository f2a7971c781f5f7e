#pragma once
// The panel figures (views/panel_figure.h) of a single-wheel test file: its
// drawbar pull and lateral force against slip, one panel per slip angle,
// with a model's curve and a band of +-2 sigma of the model's held-out
// residuals; and those residuals against slip angle. The model is the
// single-wheel study's final model when the study has run (the report), else
// the baseline of the family the study starts from, with nothing fitted (so
// its residuals are held out by construction).

#include <optional>
#include <string>
#include <vector>

#include "app/views_input.h"
#include "core/discrepancy/single_wheel/study.h"
#include "core/terramechanics/model_grid.h"
#include "views/panel_figure.h"

namespace roverlab::app {

// The model a single-wheel figure draws, with its held-out residuals.
struct SingleWheelModel {
  std::string name;  // e.g. "baseline Ishigami (slip angle) on dry_sand, travel slip"
  terramechanics::GridModel model;
  bool at_slip_angle = false;  // evaluated with the points' slip angles (slip-angle families)
  std::vector<terramechanics::PointResidual> held_out;
  std::string held_out_method;  // "nothing fitted" or the study's ("leave-one-out", "10-fold", ...)
};

// The baseline on `soil`: Wong-Reece, or Ishigami at a slip angle; the
// slip's reading (longitudinal or travel) the one whose residuals are the
// smaller in the stated sigmas, and said so in the name.
SingleWheelModel baseline_single_wheel_model(const terramechanics::Soil& soil,
                                             const std::vector<terramechanics::WheelTestPoint>& points);

// The study's final model (its forward selection's chain, else its baseline)
// with its held-out predictions.
SingleWheelModel final_single_wheel_model(const terramechanics::Soil& soil,
                                          const std::vector<terramechanics::WheelTestPoint>& points,
                                          const analysis::DiscrepancyReport& report);

// sqrt(mean((measured - predicted)^2)) of one quantity over the finite residuals; NaN when none.
double rms_residual(const std::vector<terramechanics::PointResidual>& residuals, terramechanics::Quantity q);

// The slip panels and residuals figures of `points` drawn with `model`.
views::LabFigures single_wheel_figures(const std::vector<terramechanics::WheelTestPoint>& points,
                                       const SingleWheelModel& model);

// The figures of the file `in` (a single-wheel CSV): the baseline on
// `soil` (default dry_sand); LabFigures::why_not says why there are none.
views::LabFigures lab_figures_of(const ViewInput& in, const std::optional<std::string>& soil);

}  // namespace roverlab::app
