#pragma once
// Small multiples of lab data (issue 44): rows of 2D panels sharing their x
// axis across the figure and their y axis along a row, each panel holding
// measured points and a model's curve with a band around it, in groups (a
// wheel at a load, a plate) coloured alike in every panel and named in a key.
// The single-wheel views (drawbar pull and lateral force against slip, one
// panel per slip angle; residuals against slip angle) and the plate view
// (force against depth with the fitted curves) are figures of this kind: the
// app builds them (app/lab_figures.h), views/panel_figure_scene.cpp draws them.

#include <cmath>
#include <optional>
#include <string>
#include <vector>

namespace roverlab::views {

// One group's points and curve in one panel.
struct PanelSeries {
  int group = 0;                         // its colour and key entry (PanelFigure::group_names)
  std::vector<double> x, y;              // measured points
  std::vector<double> curve_x, curve_y;  // the model's curve; NaN where the model has no value
  double band = NAN;                     // the band's half-width around the curve; NaN: no band
};

struct Panel {
  std::string title;  // e.g. "slip angle 30 deg"
  std::vector<PanelSeries> series;
};

// A row: one quantity, its panels side by side, one y axis range.
struct PanelRow {
  std::string y_title;  // e.g. "drawbar pull (N)"
  std::vector<Panel> panels;
};

struct PanelFigure {
  std::string caption;  // the first line: what the curves and the band are
  std::string x_title;  // e.g. "slip"
  std::vector<PanelRow> rows;
  std::vector<std::string> group_names;  // group g's name at g
  std::vector<std::string> notes;        // what the figure leaves out, one sentence each
};

// The axis ranges a figure is drawn with: every point, curve value and band
// edge inside, 5 % either side (a degenerate range gets +-1).
struct PanelRanges {
  double x_min = 0, x_max = 1;
  std::vector<double> y_min, y_max;  // per row
};
PanelRanges panel_ranges(const PanelFigure& figure);

// The figures of a lab test file the app built (absent: the file has none).
struct LabFigures {
  std::optional<PanelFigure> slip_panels;  // drawbar pull, lateral force against slip per slip angle
  std::optional<PanelFigure> residuals;    // held-out residuals against slip angle
  std::optional<PanelFigure> force_depth;  // plate force against depth with the fitted curves
  std::string why_not;                     // why a figure is absent, one line
};

}  // namespace roverlab::views
