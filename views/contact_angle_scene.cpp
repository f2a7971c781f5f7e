#include "views/contact_angle_scene.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCubeSource.h>
#include <vtkNew.h>
#include <vtkProperty.h>
#include <vtkRegularPolygonSource.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkTransform.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/common/error.h"
#include "core/estimation/contact_angle/model_selection.h"
#include "core/estimation/contact_angle/streams.h"
#include "views/vtk_parts.h"

namespace roverlab::views {

namespace {

vtkSmartPointer<vtkActor> flat_actor(vtkAlgorithmOutput* port, const double rgb[3]) {
  auto a = actor_of(port, Eigen::Vector3d(rgb[0], rgb[1], rgb[2]));
  a->GetProperty()->SetLighting(false);
  return a;
}

vtkSmartPointer<vtkActor> arrow(const double rgb[3], double width) {
  return unlit_arrow(Eigen::Vector3d(rgb[0], rgb[1], rgb[2]), 0.03 * width, 0.08 * width, 0.25, 16);
}

// Places an arrow of length `len` from (x, y) at angle `a` (rad, counter-clockwise from +x).
void aim(vtkActor* actor, double x, double y, double a, double len) {
  vtkNew<vtkTransform> t;
  t->Translate(x, y, 0.1);
  t->RotateZ(a * 180.0 / M_PI);
  t->Scale(len, len, len);
  actor->SetUserTransform(t);
}

// The still parts of a panel: the wheel disc on the ground seen from the
// side (left part), the wheel seen from above (right part).
void add_wheel_outlines(vtkRenderer* r) {
  const double disc_rgb[3] = {0.82, 0.82, 0.84}, ground_rgb[3] = {0.62, 0.56, 0.47},
               wheel_top_rgb[3] = {0.55, 0.55, 0.58};
  vtkNew<vtkRegularPolygonSource> disc;
  disc->SetNumberOfSides(64);
  disc->SetRadius(1.0);
  disc->SetCenter(0.0, 0.0, 0.0);
  r->AddActor(flat_actor(disc->GetOutputPort(), disc_rgb));
  vtkNew<vtkCubeSource> ground;
  ground->SetBounds(-1.6, 1.6, -1.12, -1.0, -0.01, 0.01);
  r->AddActor(flat_actor(ground->GetOutputPort(), ground_rgb));
  vtkNew<vtkCubeSource> top;
  top->SetBounds(1.45, 2.85, 0.7, 1.0, -0.01, 0.01);  // the wheel seen from above
  r->AddActor(flat_actor(top->GetOutputPort(), wheel_top_rgb));
}

}  // namespace

std::string contact_angle_needs(const log::Log& lg) {
  const log::Stream* estimate = lg.find_stream(estimation::contact_streams::kWheels);
  if (estimate == nullptr) {
    return "no contact-angle estimates (stream estimate/contact/wheels): run `roverlab estimate contact-angle` "
           "(the log needs imu, joints and wheels of a DH rover)";
  }
  for (const auto& c : estimate->channels()) {
    if (c.name.rfind("contact_angle_", 0) == 0) return {};
  }
  return "stream estimate/contact/wheels has no contact_angle_<wheel> channels";
}

// One wheel's panel: its renderer, the estimate's and truth's arrows, its text.
struct ContactAngleScene::Panel {
  vtkSmartPointer<vtkRenderer> renderer;
  vtkSmartPointer<vtkActor> est, truth, est_ss, truth_ss;
  vtkSmartPointer<vtkTextActor> text;
};

struct ContactAngleScene::Parts {
  std::vector<Panel> panels;
  std::vector<vtkSmartPointer<vtkRenderer>> renderers;
  const log::Stream* estimate = nullptr;
  const log::Stream* reference = nullptr;
  std::vector<double> shown;
};

ContactAngleScene::ContactAngleScene(const log::Log& lg) {
  const std::string missing = contact_angle_needs(lg);
  if (!missing.empty()) throw DataError(missing);
  parts_ = std::make_unique<Parts>();
  Parts& p = *parts_;
  p.estimate = lg.find_stream(estimation::contact_streams::kWheels);
  p.reference = lg.find_stream("truth/wheels");
  for (const auto& c : p.estimate->channels()) {
    if (c.name.rfind("contact_angle_", 0) == 0) wheels_.push_back(c.name.substr(14));
  }
  t0_ = p.estimate->start_time();
  t1_ = p.estimate->end_time();
  for (std::size_t w = 0; w < wheels_.size(); ++w) {
    p.panels.push_back(make_panel(w));
    p.renderers.push_back(p.panels.back().renderer);
  }
  p.shown.assign(wheels_.size(), NAN);
  set_time(t0_);
}

ContactAngleScene::~ContactAngleScene() = default;

// Panels: left wheels on the top row (front to rear), right wheels below.
ContactAngleScene::Panel ContactAngleScene::make_panel(std::size_t w) const {
  const std::size_t n = wheels_.size(), cols = (n + 1) / 2;
  const std::string& name = wheels_[w];
  // Seed 000's order FL ML RL RR MR FR: the right side comes back rear to front.
  const bool left = name.size() > 1 && name[1] == 'L';
  std::size_t col = w < cols ? w : n - 1 - w;
  if (col >= cols) col = cols - 1;
  const double x0 = static_cast<double>(col) / static_cast<double>(cols),
               x1 = static_cast<double>(col + 1) / static_cast<double>(cols);
  const double y0 = left ? 0.5 : 0.0, y1 = left ? 1.0 : 0.5;
  Panel panel;
  auto& r = panel.renderer = vtkSmartPointer<vtkRenderer>::New();
  r->SetViewport(x0, y0, x1, y1);
  r->SetBackground(0.97, 0.97, 0.99);
  add_wheel_outlines(r);
  panel.est = arrow(estimate_rgb, 1.3);
  panel.truth = arrow(truth_rgb, 0.8);
  panel.est_ss = arrow(estimate_rgb, 1.0);
  panel.truth_ss = arrow(truth_rgb, 0.6);
  for (auto& a : {panel.est, panel.truth, panel.est_ss, panel.truth_ss}) r->AddActor(a);
  panel.truth->SetVisibility(parts_->reference != nullptr);
  panel.truth_ss->SetVisibility(parts_->reference != nullptr);
  panel.text = vtkSmartPointer<vtkTextActor>::New();
  panel.text->GetTextProperty()->SetFontSize(14);
  panel.text->GetTextProperty()->SetColor(0.05, 0.05, 0.1);
  panel.text->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  panel.text->GetPositionCoordinate()->SetValue(0.03, 0.04);
  r->AddViewProp(panel.text);
  vtkCamera* cam = r->GetActiveCamera();
  cam->ParallelProjectionOn();
  cam->SetFocalPoint(0.85, -0.1, 0.0);
  cam->SetPosition(0.85, -0.1, 10.0);
  cam->SetViewUp(0, 1, 0);
  cam->SetParallelScale(1.55);
  return panel;
}

const std::vector<vtkSmartPointer<vtkRenderer>>& ContactAngleScene::renderers() const { return parts_->renderers; }

void ContactAngleScene::attach(vtkRenderWindow* window) {
  for (const auto& r : parts_->renderers) window->AddRenderer(r);
}

void ContactAngleScene::detach(vtkRenderWindow* window) {
  for (const auto& r : parts_->renderers) window->RemoveRenderer(r);
}

double ContactAngleScene::shown_contact_angle(std::size_t w) const { return parts_->shown.at(w); }

void ContactAngleScene::set_time(double t) {
  const Parts& p = *parts_;
  const std::size_t k = p.estimate->nearest_index(t);
  const std::size_t kr = p.reference ? p.reference->nearest_index(t) : 0;
  for (std::size_t w = 0; w < wheels_.size(); ++w) show_panel(w, k, kr);
}

void ContactAngleScene::show_panel(std::size_t w, std::size_t k, std::size_t kr) {
  Parts& p = *parts_;
  Panel& panel = p.panels[w];
  auto value = [](const log::Stream* s, const std::string& c, std::size_t i) {
    const log::Channel* ch = s ? s->find_channel(c) : nullptr;
    return ch ? ch->values[i] : NAN;
  };
  // Fit the panel (side view -1.2..1.1, top view to 2.9, in x) whatever its aspect.
  const int* size = panel.renderer->GetRenderWindow() ? panel.renderer->GetSize() : nullptr;
  if (size != nullptr && size[0] > 0 && size[1] > 0) {
    const double aspect = static_cast<double>(size[0]) / static_cast<double>(size[1]);
    panel.renderer->GetActiveCamera()->SetParallelScale(std::max(1.55, 2.15 / aspect));
  }
  const std::string& n = wheels_[w];
  const double g = value(p.estimate, "contact_angle_" + n, k), b = value(p.estimate, "side_slip_" + n, k);
  const double gt = value(p.reference, "contact_angle_" + n, kr), bt = value(p.reference, "side_slip_" + n, kr);
  p.shown[w] = g;
  // Side view: forward is +x, up is +y; an upward wheel velocity is a positive contact angle.
  panel.est->SetVisibility(std::isfinite(g));
  if (std::isfinite(g)) aim(panel.est, 0.0, 0.0, g, 1.45);
  panel.truth->SetVisibility(std::isfinite(gt));
  if (std::isfinite(gt)) aim(panel.truth, 0.0, 0.0, gt, 1.2);
  // Top view: forward is +x, left is +y; a leftward velocity is a positive side slip.
  panel.est_ss->SetVisibility(std::isfinite(b));
  if (std::isfinite(b)) aim(panel.est_ss, 1.55, 0.2, b, 1.2);
  panel.truth_ss->SetVisibility(std::isfinite(bt) && std::isfinite(b));
  if (std::isfinite(bt)) aim(panel.truth_ss, 1.55, 0.2, bt, 1.0);
  char line[200];
  // Degrees to one decimal, never "-0.0" (a truth of -0.01 deg reads as a sign it does not have).
  const auto deg = [](double rad) {
    const double v = std::round(rad * 1800.0 / M_PI) / 10.0;
    return v == 0.0 ? 0.0 : v;
  };
  int len = std::snprintf(line, sizeof line, "%s  contact %s", n.c_str(), std::isfinite(g) ? "" : "undefined");
  if (std::isfinite(g)) len += std::snprintf(line + len, sizeof line - len, "%.1f deg", deg(g));
  if (std::isfinite(gt)) len += std::snprintf(line + len, sizeof line - len, " (truth %.1f)", deg(gt));
  if (std::isfinite(b)) len += std::snprintf(line + len, sizeof line - len, "\nside slip %.1f deg", deg(b));
  if (std::isfinite(b) && std::isfinite(bt)) std::snprintf(line + len, sizeof line - len, " (truth %.1f)", deg(bt));
  // The first panel names the estimates' model (chosen by the data, or set by hand and maybe rejected).
  std::string model = w == 0 ? estimation::model_label(*parts_->estimate) : "";
  if (w == 0 && std::isfinite(gt))
    model += (model.empty() ? "" : "\n") + std::string("arrows: blue estimate, green truth");
  panel.text->SetInput(model.empty() ? line : (std::string(line) + "\n" + model).c_str());
}

namespace {

class ContactAnglesView : public View {
 public:
  std::string name() const override { return "contact-angles"; }
  std::string title() const override { return "Contact angles"; }
  std::string heading() const override { return "Contact and side-slip angles"; }
  std::vector<std::string> estimates_drawn() const override { return {estimation::contact_streams::kPrefix}; }
  std::string needs(const SceneInput& in) const override { return contact_angle_needs(*in.log); }
  // Without the estimator's streams and without what it needs, no analysis can feed the view.
  std::string needs_before_estimates(const log::Log& lg) const override {
    if (lg.find_stream(estimation::contact_streams::kWheels) != nullptr) return {};
    for (const char* s : {"imu", "joints", "wheels"}) {
      if (lg.find_stream(s) == nullptr) return contact_angle_needs(lg);
    }
    return {};
  }

 protected:
  std::unique_ptr<Scene> make_scene(const SceneInput& in) const override {
    return std::make_unique<ContactAngleScene>(*in.log);
  }
};

}  // namespace

std::unique_ptr<View> make_contact_angles_view() { return std::make_unique<ContactAnglesView>(); }

}  // namespace roverlab::views
