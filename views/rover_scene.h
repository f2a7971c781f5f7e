#pragma once
// The rover view: a four-wheel skid-steer rover (seed 002's Pathfinder
// geometry) posed by the log's attitude and position at a time, wheels
// coloured by slip class, a velocity arrow, and the tracks of every pose
// source in the log (INS estimate, wheel odometry, GPS, truth) on a ground
// plane. Truth, when present, is drawn as a ghost rover beside the estimate.
// World axes: x east, y north, z up; height is not shown (the ground is flat).

#include <string>
#include <vector>

#include <vtkSmartPointer.h>
#include <Eigen/Core>

#include "core/log/log.h"
#include "core/models/skid_steer_odometry.h"
#include "views/view.h"

class vtkPolyData;
class vtkRenderer;

namespace roverlab::views {

// A pose track from one stream: east/north (m) and roll/pitch/yaw (rad, yaw
// clockwise from north). Missing angles are 0; yaw from the course when the
// stream has none.
struct PoseTrack {
  std::string source;  // stream name
  std::vector<double> time, east, north, roll, pitch, yaw;
  bool empty() const { return time.empty(); }
  // Pose at t (linear interpolation, yaw unwrapped; clamped to the ends).
  struct Pose {
    double east = 0, north = 0, roll = 0, pitch = 0, yaw = 0;
  };
  Pose at(double t) const;
};

// The pose tracks a log holds, best first: estimate/ins/pose, truth/motion,
// estimate/odometry/pose, gps.
std::vector<PoseTrack> pose_tracks(const log::Log& log);
// Empty when the log holds a pose track, else the note saying it has none.
std::string pose_track_needs(const log::Log& log);

// Class colours of seed 002's five slip classes (none .. extreme), RGB 0..1;
// grey for undefined.
Eigen::Vector3d slip_class_colour(int slip_class);

class RoverScene : public Scene {
 public:
  explicit RoverScene(const log::Log& log, const estimation::SkidSteerGeometry& rover = {});
  ~RoverScene() override;

  vtkRenderer* renderer() const;
  void attach(vtkRenderWindow* window) override;
  void detach(vtkRenderWindow* window) override;
  // Poses the rover(s), colours the wheels and moves the chase camera.
  void set_time(double t) override;
  double start_time() const override { return start_; }
  double end_time() const override { return end_; }
  // What the log lacks for this view, one sentence each.
  std::vector<std::string> notes() const override { return notes_; }
  const std::string& pose_source() const { return pose_source_; }
  // Slip class shown on the wheels at the last set_time (-1: none).
  int shown_slip_class() const { return shown_class_; }
  // World position of the rover body centre at the last set_time.
  Eigen::Vector3d rover_position() const { return position_; }
  // The legend's names, and the symbol drawn before each (a filled swatch).
  const std::vector<std::string>& legend_entries() const { return legend_entries_; }
  vtkPolyData* legend_symbol() const;
  // Colour the body is drawn in (RGB 0..1): tests look for it.
  static Eigen::Vector3d body_colour() { return {0.93, 0.93, 0.95}; }

 private:
  struct Parts;
  void read_log(const log::Log& log);
  void add_ground();
  void add_tracks();
  void add_rovers();
  void add_text();
  double speed_at(double t) const;
  void show_slip(double t);
  void show_text(double t, double speed, double yaw);
  void chase(double east, double north, double yaw);

  std::unique_ptr<Parts> parts_;
  std::vector<PoseTrack> tracks_;
  std::vector<std::string> notes_;
  std::vector<std::string> legend_entries_;
  vtkSmartPointer<vtkPolyData> legend_symbol_;
  std::string pose_source_;
  double start_ = 0, end_ = 0;
  int shown_class_ = -1;
  double shown_slip_ = 0;
  Eigen::Vector3d position_ = Eigen::Vector3d::Zero();
};

}  // namespace roverlab::views
