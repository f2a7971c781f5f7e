#pragma once
// The traction-surface view: a fitted (or model) polynomial DP(W, s),
// tau_R(W, s) or F_y(W, s) at one slip angle as a 3D surface coloured by value, with labelled axes in real
// units, a colour bar, the data points as spheres and each point's residual
// as a line to the surface (points in groups, e.g. the wheels a rover's
// estimates come from, are coloured by group and named in a key), and optionally a reference
// surface (the true local model) drawn translucent grey in the same axes.
// Axes are scaled to a unit box for display.

#include <optional>
#include <string>
#include <vector>

#include <vtkSmartPointer.h>

#include "core/terramechanics/traction_surface.h"

class vtkRenderer;

namespace roverlab::views {

struct TractionSurfaceData {
  terramechanics::PolynomialSurface surface;
  std::vector<terramechanics::SurfaceSample> points;           // may be empty
  std::vector<int> point_group;                                // per point, 1..: its colour (empty: all dark)
  std::vector<std::string> group_names;                        // group g's name at g - 1: the key (e.g. wheels)
  std::optional<terramechanics::PolynomialSurface> reference;  // drawn translucent grey
  std::string quantity = "drawbar pull", unit = "N";
  double load_min = 0, load_max = 200, slip_min = 0, slip_max = 1;
};

struct TractionSurfaceScene {
  vtkSmartPointer<vtkRenderer> renderer;
  double value_min = 0, value_max = 0;  // range of the coloured surface
};

TractionSurfaceScene make_traction_surface_scene(const TractionSurfaceData& data, int grid = 60);

// The colour of point group g (1, 2, 3, ...: green, purple, brown, cycling; RGB 0..1).
void group_colour(int group, double rgb[3]);

// The colour the surface's lookup table gives to a value in [min, max] (RGB 0..1).
void surface_colour(double fraction, double rgb[3]);

}  // namespace roverlab::views
