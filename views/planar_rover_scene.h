#pragma once
// The rover view of a planar rocker-bogie log (seed 003, one side seen from
// the side): the terrain profile traced by the wheel centres (one wheel
// radius below), the body/rocker and bogie links, the three wheels coloured
// by slip class, at the timeline's time.

#include <string>

#include <Eigen/Core>
#include <vtkSmartPointer.h>

#include "core/log/log.h"

class vtkRenderer;

namespace roverlab::views {

// True when the log has what the planar view draws (truth/pose with the
// bogie pivot and truth/wheels with the wheel centres).
bool is_planar_rocker_bogie_log(const log::Log& log);

class PlanarRoverScene {
 public:
  explicit PlanarRoverScene(const log::Log& log);  // throws DataError when is_planar_rocker_bogie_log is false
  ~PlanarRoverScene();
  PlanarRoverScene(const PlanarRoverScene&) = delete;
  PlanarRoverScene& operator=(const PlanarRoverScene&) = delete;
  vtkRenderer* renderer() const;
  void set_time(double t);
  double start_time() const { return t0_; }
  double end_time() const { return t1_; }
  // Position (x, z) of wheel i (0..2) at the last set_time.
  Eigen::Vector2d wheel_centre(int i) const;

 private:
  struct Parts;
  Parts* parts_;
  double t0_ = 0, t1_ = 0;
};

}  // namespace roverlab::views
