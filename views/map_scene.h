#pragma once
// The map view: top-down, north up, the trajectories of every pose source a
// log holds (INS estimate, simulated truth, wheel odometry, GPS; a planar
// simulation's truth along its x axis), with a scale bar, a north arrow,
// start and end marks, the slip class along the best track as colour, and a
// marker on each track at the timeline's time. Drawn with a parallel camera
// fitted so that every track is whole in the window.

#include <array>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/log/log.h"
#include "views/view.h"

class vtkRenderer;

namespace roverlab::views {

// East, north, east, north: lower-left and upper-right corners (m).
using MapRect = std::array<double, 4>;

class MapScene : public Scene {
 public:
  explicit MapScene(const log::Log& log);
  ~MapScene() override;

  vtkRenderer* renderer() const;
  void attach(vtkRenderWindow* window) override;
  void detach(vtkRenderWindow* window) override;
  // Fits the camera, the scale bar and the north arrow to the window.
  void fit_width(int pixels) override;
  // Moves each track's marker to its position at t.
  void set_time(double t) override;
  double start_time() const override { return start_; }
  double end_time() const override { return end_; }
  std::vector<std::string> notes() const override { return notes_; }

  // What a test reads from the scene. The tracks drawn (stream names, best first).
  std::vector<std::string> sources() const;
  // The bounds of the actor drawing track k, as VTK computes them.
  MapRect track_bounds(std::size_t k) const;
  // The ground the camera shows at the last fit (from the camera itself).
  MapRect visible() const;
  // The scale bar: its length (m, 1, 2 or 5 times a power of ten) and its label.
  double scale_length() const;
  std::string scale_text() const;
  // The legend's entries, in order (tracks, then the slip classes drawn).
  std::vector<std::string> legend_entries() const;
  // Segments of the best track coloured by slip class, per class (none .. extreme).
  std::array<int, 5> slip_segments() const { return slip_segments_; }
  // Where track k's marker is (east, north).
  Eigen::Vector2d marker(std::size_t k) const;
  // The colour track k is drawn in (RGB 0..1).
  static Eigen::Vector3d track_colour(const std::string& source);

 private:
  struct Parts;
  struct Track;
  void read_log(const log::Log& log);
  void add_tracks();
  void add_slip(const log::Log& log);
  void add_marks();
  void add_legend();
  void fit(double aspect);

  std::unique_ptr<Parts> parts_;
  std::vector<Track> tracks_;
  std::vector<std::string> notes_;
  std::array<int, 5> slip_segments_{};
  MapRect extent_{};  // every track's finite points
  double start_ = 0, end_ = 0;
};

// Empty when the log holds a track the map can draw, else why not.
std::string map_needs(const log::Log& log);

}  // namespace roverlab::views
