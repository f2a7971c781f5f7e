#include "views/ghost_rover_scene.h"

#include <vtkActor.h>
#include <vtkActor2DCollection.h>
#include <vtkActorCollection.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>

#include <cmath>

#include "core/common/error.h"

namespace roverlab::views {

namespace {

// Run B's renderer as a ghost layer: its rover semi-transparent, its flat
// parts (ground, tracks: no height) and its text hidden, A's camera.
void make_ghost(vtkRenderer* ghost, vtkRenderer* base) {
  ghost->SetLayer(1);
  ghost->SetPreserveDepthBuffer(true);  // A's rover hides what of B is behind it
  ghost->SetActiveCamera(base->GetActiveCamera());
  vtkActorCollection* actors = ghost->GetActors();
  actors->InitTraversal();
  while (vtkActor* a = actors->GetNextActor()) {
    double b[6];
    a->GetBounds(b);
    const bool flat = !(b[5] - b[4] > 1e-3);
    if (flat) {
      a->VisibilityOff();
    } else {
      a->GetProperty()->SetOpacity(GhostRoverScene::kOpacity);
    }
  }
  vtkActor2DCollection* texts = ghost->GetActors2D();
  texts->InitTraversal();
  while (vtkActor2D* t = texts->GetNextActor2D()) t->VisibilityOff();
}

}  // namespace

GhostRoverScene::GhostRoverScene(const log::Log& a, const std::string& b_name, const log::Log& b,
                                 const estimation::SkidSteerGeometry& rover)
    : a_(std::make_unique<RoverScene>(a, rover)), b_(std::make_unique<RoverScene>(b, rover)), b_name_(b_name) {
  try {
    alignment_ = comparison::align_runs(a, b, comparison::AlignmentOptions{});
  } catch (const DataError& e) {
    throw DataError(b_name + ": " + e.what());
  }
  b_->set_time(0.5 * (b_->start_time() + b_->end_time()));  // posed once, so that its rover has its height
  make_ghost(b_->renderer(), a_->renderer());
}

GhostRoverScene::~GhostRoverScene() = default;

void GhostRoverScene::attach(vtkRenderWindow* window) {
  window->SetNumberOfLayers(2);
  a_->attach(window);
  b_->attach(window);
}

void GhostRoverScene::detach(vtkRenderWindow* window) {
  b_->detach(window);
  a_->detach(window);
}

void GhostRoverScene::set_time(double t) {
  const double tb = alignment_.other_times({t}).front();
  shown_ = std::isfinite(tb) && tb >= b_->start_time() && tb <= b_->end_time();
  if (shown_) b_->set_time(tb);  // B first: its chase camera is A's, which A then moves to its own rover
  b_->renderer()->SetDraw(shown_);
  a_->set_time(t);
}

std::vector<std::string> GhostRoverScene::notes() const {
  std::vector<std::string> out = a_->notes();
  out.push_back("ghost: " + b_name_ + " (" + b_->pose_source() + ") at " + alignment_.how);
  return out;
}

namespace {

class GhostRoverView : public View {
 public:
  std::string name() const override { return "ghost-rover"; }
  std::string title() const override { return "Ghost rover"; }
  std::string heading() const override { return "The rover, and another run's as a ghost"; }
  bool compares_runs() const override { return true; }
  bool trackball_camera() const override { return true; }
  std::string needs(const SceneInput& in) const override {
    if (in.log == nullptr) return "needs a log";
    if (in.compared.empty()) return "needs another run to compare with (render --compare FILE, File > Compare with...)";
    if (std::string lacks = pose_track_needs(*in.log); !lacks.empty()) return lacks;
    if (std::string lacks = pose_track_needs(*in.compared.front().second); !lacks.empty())
      return in.compared.front().first + ": " + lacks;
    return {};
  }

 protected:
  std::unique_ptr<Scene> make_scene(const SceneInput& in) const override {
    return std::make_unique<GhostRoverScene>(*in.log, in.compared.front().first, *in.compared.front().second, in.rover);
  }
};

}  // namespace

std::unique_ptr<View> make_ghost_rover_view() { return std::make_unique<GhostRoverView>(); }

}  // namespace roverlab::views
