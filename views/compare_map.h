#pragma once
// Every run's track on one map (issue 45): the baseline's and each other
// run's position track (comparison::position_track), each in its own colour
// and named in the legend, north up at one scale on both axes, with a marker
// on each at the timeline's time (the other runs' times through the
// alignment `roverlab compare` uses). `render A --compare B --view compare-map`.

#include <string>
#include <utility>
#include <vector>

#include <vtkSmartPointer.h>
#include <Eigen/Core>

#include "core/comparison/alignment.h"
#include "core/log/log.h"
#include "views/view.h"

class vtkChartXY;
class vtkContextView;
class vtkTable;

namespace roverlab::views {

class CompareMap : public Scene {
 public:
  // Throws DataError naming a run that cannot be aligned.
  CompareMap(const log::Log& base, const std::vector<std::pair<std::string, const log::Log*>>& runs);
  ~CompareMap() override;
  void attach(vtkRenderWindow* window) override;
  void detach(vtkRenderWindow* window) override;
  void fit_width(int pixels) override;
  void set_time(double t) override;
  double start_time() const override { return start_; }
  double end_time() const override { return end_; }
  std::vector<std::string> notes() const override { return notes_; }

  // What a test reads: the tracks drawn (the baseline first), their names,
  // points (east, north; a planar simulation's x, z) and markers.
  vtkChartXY* chart() const;
  std::size_t track_count() const { return tracks_.size(); }
  const std::string& track_name(std::size_t k) const { return tracks_[k].name; }
  const std::string& track_source(std::size_t k) const { return tracks_[k].source; }
  const std::vector<double>& track_x(std::size_t k) const { return tracks_[k].x; }
  const std::vector<double>& track_y(std::size_t k) const { return tracks_[k].y; }
  // Track k's marker (NaN when its run has no position at the aligned time).
  Eigen::Vector2d marker(std::size_t k) const;

 private:
  struct Track {
    std::string name, source, x_name, y_name;  // x_name, y_name: east, north (or a planar run's x, z)
    std::vector<double> time, x, y;
    comparison::Alignment alignment;  // the run's times from the baseline's
    vtkSmartPointer<vtkTable> marker;
  };
  void add_track(const std::string& name, const log::Log& lg, const comparison::Alignment& alignment);
  void fit_axes();

  std::vector<Track> tracks_;
  std::vector<std::string> notes_;
  vtkSmartPointer<vtkContextView> view_;
  double start_ = 0, end_ = 0;
};

}  // namespace roverlab::views
