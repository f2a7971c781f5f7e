#pragma once
// One channel of a log against another as points (force against depth, slip
// against speed): `render LOG --view scatter --x STREAM:CH --y STREAM:CH`.
// Channels of one stream pair sample by sample; from two streams the y
// channel is interpolated linearly to the x channel's times (inside its span).

#include <string>
#include <vector>

#include <vtkSmartPointer.h>

#include "core/log/log.h"
#include "views/view.h"

class vtkChartXY;
class vtkContextView;

namespace roverlab::views {

// The pairs drawn: every sample of x with a finite x and y.
struct ScatterPoints {
  std::vector<double> x, y;
  bool interpolated = false;  // y from another stream, interpolated to x's times
  std::size_t x_samples = 0;  // samples of x's stream
};

// The pairs of `x` and `y` in `log`. Throws DataError naming a missing stream or channel.
ScatterPoints paired_samples(const log::Log& log, const ChannelRef& x, const ChannelRef& y);

// An axis title: "stream:channel (unit)" (no unit for "1").
std::string scatter_axis_title(const log::Log& log, const ChannelRef& c);

class ScatterScene : public Scene {
 public:
  ScatterScene(const log::Log& log, ChannelRef x, ChannelRef y);
  ~ScatterScene() override;
  void attach(vtkRenderWindow* window) override;
  void detach(vtkRenderWindow* window) override;
  bool follows_time() const override { return false; }
  void set_time(double /*t*/) override {}
  double start_time() const override { return start_; }
  double end_time() const override { return end_; }
  std::vector<std::string> notes() const override;
  vtkChartXY* chart() const { return chart_; }
  const ScatterPoints& points() const { return points_; }

 private:
  void set_axis(int axis, const std::vector<double>& values, const std::string& title);

  ScatterPoints points_;
  ChannelRef x_, y_;
  double start_ = 0, end_ = 0;
  vtkSmartPointer<vtkContextView> view_;
  vtkSmartPointer<vtkChartXY> chart_;
};

}  // namespace roverlab::views
