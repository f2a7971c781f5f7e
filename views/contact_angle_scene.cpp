#include "views/contact_angle_scene.h"

#include <vtkActor.h>
#include <vtkArrowSource.h>
#include <vtkCamera.h>
#include <vtkCubeSource.h>
#include <vtkPolyDataMapper.h>
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

namespace roverlab::views {

namespace {

vtkSmartPointer<vtkActor> actor_of(vtkAlgorithmOutput* port, const double rgb[3]) {
  auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New();
  mapper->SetInputConnection(port);
  auto a = vtkSmartPointer<vtkActor>::New();
  a->SetMapper(mapper);
  a->GetProperty()->SetColor(rgb[0], rgb[1], rgb[2]);
  a->GetProperty()->SetLighting(false);
  return a;
}

vtkSmartPointer<vtkActor> arrow(const double rgb[3], double width) {
  auto src = vtkSmartPointer<vtkArrowSource>::New();
  src->SetShaftRadius(0.03 * width);
  src->SetTipRadius(0.08 * width);
  src->SetTipLength(0.25);
  src->SetShaftResolution(16);
  src->SetTipResolution(16);
  return actor_of(src->GetOutputPort(), rgb);
}

// Places an arrow of length `len` from (x, y) at angle `a` (rad, counter-clockwise from +x).
void aim(vtkActor* actor, double x, double y, double a, double len) {
  auto t = vtkSmartPointer<vtkTransform>::New();
  t->Translate(x, y, 0.1);
  t->RotateZ(a * 180.0 / M_PI);
  t->Scale(len, len, len);
  actor->SetUserTransform(t);
}

}  // namespace

struct ContactAngleScene::Parts {
  std::vector<vtkSmartPointer<vtkRenderer>> renderers;
  std::vector<vtkSmartPointer<vtkActor>> est, truth, est_ss, truth_ss;
  std::vector<vtkSmartPointer<vtkTextActor>> text;
  const log::Stream* estimate = nullptr;
  const log::Stream* reference = nullptr;
  std::vector<double> shown;
};

ContactAngleScene::ContactAngleScene(const log::Log& lg) : parts_(new Parts) {
  Parts& p = *parts_;
  p.estimate = lg.find_stream("estimate/contact/wheels");
  if (p.estimate == nullptr) {
    delete parts_;
    throw DataError("no contact-angle estimates (stream estimate/contact/wheels): run `roverlab estimate contact-angle`");
  }
  p.reference = lg.find_stream("truth/wheels");
  for (const auto& c : p.estimate->channels()) {
    if (c.name.rfind("contact_angle_", 0) == 0) wheels_.push_back(c.name.substr(14));
  }
  if (wheels_.empty()) {
    delete parts_;
    throw DataError("stream estimate/contact/wheels has no contact_angle_<wheel> channels");
  }
  t0_ = p.estimate->start_time();
  t1_ = p.estimate->end_time();
  // Panels: left wheels on the top row (front to rear), right wheels below.
  const std::size_t n = wheels_.size(), cols = (n + 1) / 2;
  const double disc_rgb[3] = {0.82, 0.82, 0.84}, ground_rgb[3] = {0.62, 0.56, 0.47}, wheel_top_rgb[3] = {0.55, 0.55, 0.58};
  for (std::size_t w = 0; w < n; ++w) {
    const std::string& name = wheels_[w];
    // Seed 000's order FL ML RL RR MR FR: the right side comes back rear to front.
    const bool left = name.size() > 1 && name[1] == 'L';
    std::size_t col = w < cols ? w : n - 1 - w;
    if (col >= cols) col = cols - 1;
    const double x0 = static_cast<double>(col) / static_cast<double>(cols), x1 = static_cast<double>(col + 1) / static_cast<double>(cols);
    const double y0 = left ? 0.5 : 0.0, y1 = left ? 1.0 : 0.5;
    auto r = vtkSmartPointer<vtkRenderer>::New();
    r->SetViewport(x0, y0, x1, y1);
    r->SetBackground(0.97, 0.97, 0.99);
    // Side view (left part): the wheel disc on the ground; top view (right part).
    auto disc = vtkSmartPointer<vtkRegularPolygonSource>::New();
    disc->SetNumberOfSides(64);
    disc->SetRadius(1.0);
    disc->SetCenter(0.0, 0.0, 0.0);
    r->AddActor(actor_of(disc->GetOutputPort(), disc_rgb));
    auto ground = vtkSmartPointer<vtkCubeSource>::New();
    ground->SetBounds(-1.6, 1.6, -1.12, -1.0, -0.01, 0.01);
    r->AddActor(actor_of(ground->GetOutputPort(), ground_rgb));
    auto top = vtkSmartPointer<vtkCubeSource>::New();
    top->SetBounds(1.45, 2.85, 0.7, 1.0, -0.01, 0.01);  // the wheel seen from above
    r->AddActor(actor_of(top->GetOutputPort(), wheel_top_rgb));
    auto e = arrow(estimate_rgb, 1.3), tr = arrow(truth_rgb, 0.8), es = arrow(estimate_rgb, 1.0), ts = arrow(truth_rgb, 0.6);
    for (auto& a : {e, tr, es, ts}) r->AddActor(a);
    tr->SetVisibility(p.reference != nullptr);
    ts->SetVisibility(p.reference != nullptr);
    auto text = vtkSmartPointer<vtkTextActor>::New();
    text->GetTextProperty()->SetFontSize(14);
    text->GetTextProperty()->SetColor(0.05, 0.05, 0.1);
    text->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    text->GetPositionCoordinate()->SetValue(0.03, 0.04);
    r->AddViewProp(text);
    vtkCamera* cam = r->GetActiveCamera();
    cam->ParallelProjectionOn();
    cam->SetFocalPoint(0.85, -0.1, 0.0);
    cam->SetPosition(0.85, -0.1, 10.0);
    cam->SetViewUp(0, 1, 0);
    cam->SetParallelScale(1.55);
    p.renderers.push_back(r);
    p.est.push_back(e);
    p.truth.push_back(tr);
    p.est_ss.push_back(es);
    p.truth_ss.push_back(ts);
    p.text.push_back(text);
  }
  p.shown.assign(n, NAN);
  set_time(t0_);
}

ContactAngleScene::~ContactAngleScene() { delete parts_; }

const std::vector<vtkSmartPointer<vtkRenderer>>& ContactAngleScene::renderers() const { return parts_->renderers; }

double ContactAngleScene::shown_contact_angle(std::size_t w) const { return parts_->shown.at(w); }

void ContactAngleScene::set_time(double t) {
  Parts& p = *parts_;
  const std::size_t k = p.estimate->nearest_index(t);
  const std::size_t kr = p.reference ? p.reference->nearest_index(t) : 0;
  auto value = [](const log::Stream* s, const std::string& c, std::size_t i) {
    const log::Channel* ch = s ? s->find_channel(c) : nullptr;
    return ch ? ch->values[i] : NAN;
  };
  for (std::size_t w = 0; w < wheels_.size(); ++w) {
    // Fit the panel (side view -1.2..1.1, top view to 2.9, in x) whatever its aspect.
    const int* size = p.renderers[w]->GetRenderWindow() ? p.renderers[w]->GetSize() : nullptr;
    if (size != nullptr && size[0] > 0 && size[1] > 0) {
      const double aspect = static_cast<double>(size[0]) / static_cast<double>(size[1]);
      p.renderers[w]->GetActiveCamera()->SetParallelScale(std::max(1.55, 2.15 / aspect));
    }
    const std::string& n = wheels_[w];
    const double g = value(p.estimate, "contact_angle_" + n, k), b = value(p.estimate, "side_slip_" + n, k);
    const double gt = value(p.reference, "contact_angle_" + n, kr), bt = value(p.reference, "side_slip_" + n, kr);
    p.shown[w] = g;
    // Side view: forward is +x, up is +y; an upward wheel velocity is a positive contact angle.
    p.est[w]->SetVisibility(std::isfinite(g));
    if (std::isfinite(g)) aim(p.est[w], 0.0, 0.0, g, 1.45);
    p.truth[w]->SetVisibility(std::isfinite(gt));
    if (std::isfinite(gt)) aim(p.truth[w], 0.0, 0.0, gt, 1.2);
    // Top view: forward is +x, left is +y; a leftward velocity is a positive side slip.
    p.est_ss[w]->SetVisibility(std::isfinite(b));
    if (std::isfinite(b)) aim(p.est_ss[w], 1.55, 0.2, b, 1.2);
    p.truth_ss[w]->SetVisibility(std::isfinite(bt) && std::isfinite(b));
    if (std::isfinite(bt)) aim(p.truth_ss[w], 1.55, 0.2, bt, 1.0);
    char line[200];
    const double d = 180.0 / M_PI;
    int len = std::snprintf(line, sizeof line, "%s  contact %s", n.c_str(), std::isfinite(g) ? "" : "undefined");
    if (std::isfinite(g)) len += std::snprintf(line + len, sizeof line - len, "%.1f deg", g * d);
    if (std::isfinite(gt)) len += std::snprintf(line + len, sizeof line - len, " (truth %.1f)", gt * d);
    if (std::isfinite(b)) len += std::snprintf(line + len, sizeof line - len, "\nside slip %.1f deg", b * d);
    if (std::isfinite(b) && std::isfinite(bt)) std::snprintf(line + len, sizeof line - len, " (truth %.1f)", bt * d);
    p.text[w]->SetInput(line);
  }
}

}  // namespace roverlab::views
