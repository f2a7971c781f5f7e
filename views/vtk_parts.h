#pragma once
// The small VTK pieces every scene repeats: an actor drawing a source's
// output or a poly data through its own mapper, polylines and line segments
// built from points, unlit arrows, and the unlit line style the scenes draw tracks,
// links and residuals in.

#include <utility>
#include <vector>

#include <vtkSmartPointer.h>
#include <Eigen/Core>

class vtkActor;
class vtkAlgorithmOutput;
class vtkPolyData;
class vtkTable;

namespace roverlab::views {

// An actor of colour `rgb` (0..1) drawing `port` through a new mapper.
vtkSmartPointer<vtkActor> actor_of(vtkAlgorithmOutput* port, const Eigen::Vector3d& rgb);
// An actor of colour `rgb` drawing `data` through a new mapper.
vtkSmartPointer<vtkActor> actor_of(vtkPolyData* data, const Eigen::Vector3d& rgb);

// An unlit arrow of colour `rgb` (vtkArrowSource: along +x, length 1) with
// the given shaft and tip radii, tip length and resolution of both.
vtkSmartPointer<vtkActor> unlit_arrow(const Eigen::Vector3d& rgb, double shaft_radius, double tip_radius,
                                      double tip_length, int resolution);

// Places `actor`, drawing a unit +x arrow, at `from` along `direction`,
// `length` long (its user transform).
void place_arrow(vtkActor* actor, const Eigen::Vector3d& from, const Eigen::Vector3d& direction, double length);

// One polyline cell through `points`, in order.
vtkSmartPointer<vtkPolyData> polyline(const std::vector<Eigen::Vector3d>& points);
// Line segments: one two-point cell from each point to the next (a path),
// or, with `pairs`, from points 2k to 2k + 1.
vtkSmartPointer<vtkPolyData> segments(const std::vector<Eigen::Vector3d>& points, bool pairs = false);

// A unit square, filled: a legend's colour swatch.
vtkSmartPointer<vtkPolyData> legend_swatch();

// The polyline/mapper/actor triple: `lines` drawn unlit, `width` pixels wide.
vtkSmartPointer<vtkActor> line_actor(vtkPolyData* lines, const Eigen::Vector3d& rgb, double width);
vtkSmartPointer<vtkActor> line_actor(vtkAlgorithmOutput* port, const Eigen::Vector3d& rgb, double width);

// A chart's table: one double column per (name, values) pair.
vtkSmartPointer<vtkTable> table_of(const std::vector<std::pair<const char*, std::vector<double>>>& columns);

// Moves a chart's cursor, a two-row table (time, value) drawn as a line, to
// time `t`, spanning the plot's value `range` (low, high).
void move_cursor(vtkTable* cursor, double t, const std::pair<double, double>& range);

}  // namespace roverlab::views
