#pragma once
// The rover view of a planar rocker-bogie log (seed 003) in 3D: the planar
// simulation's side (rocker and bogie links, three wheels of the log's
// radius, coloured by slip class) drawn on both sides of a body box, the
// other side mirrored at a track equal to the wheelbase (the planar model has
// no track); the terrain profile traced by the wheel centres (one wheel
// radius below) extruded across the track as a surface; at the timeline's
// time, seen obliquely from the front left. At each wheel's contact point,
// on the outer face of both sides, the direction of the path at the contact
// angle: the net-traction estimate (seed 003 Eq. 5.56) in blue with its
// 1-sigma fan, the truth in green.

#include <memory>
#include <string>
#include <vector>

#include <vtkSmartPointer.h>
#include <Eigen/Core>

#include "core/log/log.h"
#include "views/view.h"

class vtkRenderer;

namespace roverlab::views {

// True when the log has what the planar view draws (truth/pose with the
// bogie pivot and truth/wheels with the wheel centres).
bool is_planar_rocker_bogie_log(const log::Log& log);
// What keeps a planar rocker-bogie log's rover from being drawn (its pose
// has no finite value); empty when it can be.
std::string planar_rover_needs(const log::Log& log);

class PlanarRoverScene : public Scene {
 public:
  explicit PlanarRoverScene(const log::Log& log);  // throws DataError when is_planar_rocker_bogie_log is false
  ~PlanarRoverScene() override;
  vtkRenderer* renderer() const;
  void attach(vtkRenderWindow* window) override;
  void detach(vtkRenderWindow* window) override;
  void set_time(double t) override;
  double start_time() const override { return t0_; }
  double end_time() const override { return t1_; }
  // Position (x, z) of wheel i (0..2) at the last set_time.
  Eigen::Vector2d wheel_centre(int i) const;
  // Unit direction (x, z) of wheel i's contact arrow at the last set_time:
  // the estimate's (`truth` false) or the truth's; NaN when the log has none.
  Eigen::Vector2d contact_direction(int i, bool truth) const;
  std::vector<std::string> notes() const override { return notes_; }
  // The drawn track (m, between the two sides' wheel planes) and wheel width.
  double track() const;
  double wheel_width() const;

 private:
  struct Parts;
  void add_terrain();
  void add_links_and_wheels();
  void add_text_and_camera();
  void add_contact_arrows();
  void place_contact_arrows(double t);
  void show_text(double t, std::size_t k, std::size_t kw);
  std::unique_ptr<Parts> parts_;
  std::vector<std::string> notes_;
  double t0_ = 0, t1_ = 0;
};

}  // namespace roverlab::views
