#pragma once
// The rover view of another run as a ghost (issue 45): run A's rover view
// (views/rover_scene.h) with run B's rover drawn over it, semi-transparent,
// at the time the alignment maps A's time to (the clocks as recorded, as
// `roverlab compare` by default). B's ground, tracks and text are left out:
// only its rover. `render A --compare B --view ghost-rover`.

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/comparison/alignment.h"
#include "views/rover_scene.h"

namespace roverlab::views {

class GhostRoverScene : public Scene {
 public:
  // Throws DataError naming run B when it cannot be aligned.
  GhostRoverScene(const log::Log& a, const std::string& b_name, const log::Log& b,
                  const estimation::SkidSteerGeometry& rover);
  ~GhostRoverScene() override;
  void attach(vtkRenderWindow* window) override;
  void detach(vtkRenderWindow* window) override;
  void set_time(double t) override;
  double start_time() const override { return a_->start_time(); }
  double end_time() const override { return a_->end_time(); }
  std::vector<std::string> notes() const override;

  // What a test reads: each rover's body centre at the last set_time, and the ghost's opacity.
  Eigen::Vector3d position() const { return a_->rover_position(); }
  Eigen::Vector3d ghost_position() const { return b_->rover_position(); }
  double ghost_opacity() const { return kOpacity; }
  // False when run B has no pose at the aligned time (the ghost is hidden).
  bool ghost_shown() const { return shown_; }
  static constexpr double kOpacity = 0.35;

 private:
  std::unique_ptr<RoverScene> a_, b_;
  std::string b_name_;
  comparison::Alignment alignment_;
  bool shown_ = false;
};

}  // namespace roverlab::views
