#include "views/planar_rover_scene.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkLineSource.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkProperty.h>
#include <vtkRegularPolygonSource.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "core/common/error.h"
#include "core/estimation/slip.h"
#include "views/rover_scene.h"
#include "views/vtk_parts.h"

namespace roverlab::views {

bool is_planar_rocker_bogie_log(const log::Log& lg) {
  const log::Stream* p = lg.find_stream("truth/pose");
  const log::Stream* w = lg.find_stream("truth/wheels");
  return p && w && p->find_channel("bogie_pivot_x") && p->find_channel("x") && w->find_channel("centre_x_1") &&
         w->find_channel("centre_z_3") && p->size() >= 2;
}

struct PlanarRoverScene::Parts {
  vtkSmartPointer<vtkRenderer> renderer;
  vtkSmartPointer<vtkRegularPolygonSource> wheel[3];
  vtkSmartPointer<vtkActor> wheel_actor[3];
  vtkSmartPointer<vtkLineSource> link[4];  // body->wheel 1, body->bogie pivot, pivot->wheel 2, pivot->wheel 3
  vtkSmartPointer<vtkTextActor> text;
  const log::Stream* pose = nullptr;
  const log::Stream* wheels = nullptr;
  double radius = 0.075;
  Eigen::Vector2d centre[3];
};

PlanarRoverScene::PlanarRoverScene(const log::Log& lg) {
  if (!is_planar_rocker_bogie_log(lg))
    throw DataError("not a planar rocker-bogie log (truth/pose and truth/wheels with positions)");
  parts_ = std::make_unique<Parts>();
  Parts& p = *parts_;
  p.pose = lg.find_stream("truth/pose");
  p.wheels = lg.find_stream("truth/wheels");
  const auto r = lg.metadata.extra.find("truth/wheel_radius_m");
  if (r != lg.metadata.extra.end()) p.radius = std::stod(r->second);
  t0_ = p.pose->start_time();
  t1_ = p.pose->end_time();
  p.renderer = vtkSmartPointer<vtkRenderer>::New();
  p.renderer->SetBackground(0.95, 0.96, 0.98);
  add_terrain();
  add_links_and_wheels();
  add_text_and_camera();
  set_time(t0_);
}

PlanarRoverScene::~PlanarRoverScene() = default;

// Terrain: the wheel centres' tracks, a wheel radius lower, sorted along x.
void PlanarRoverScene::add_terrain() {
  Parts& p = *parts_;
  std::map<double, double> profile;
  for (int i = 1; i <= 3; ++i) {
    const auto& xs = p.wheels->channel("centre_x_" + std::to_string(i)).values;
    const auto& zs = p.wheels->channel("centre_z_" + std::to_string(i)).values;
    for (std::size_t k = 0; k < xs.size(); ++k) profile[std::round(xs[k] * 1000.0) / 1000.0] = zs[k] - p.radius;
  }
  std::vector<Eigen::Vector3d> points;
  points.reserve(profile.size());
  for (const auto& [x, z] : profile) points.emplace_back(x, z, 0.0);
  p.renderer->AddActor(line_actor(segments(points), {0.55, 0.45, 0.3}, 4.0));
}

// The body/rocker and bogie links, and the three wheels.
void PlanarRoverScene::add_links_and_wheels() {
  Parts& p = *parts_;
  for (auto& link : p.link) {
    link = vtkSmartPointer<vtkLineSource>::New();
    p.renderer->AddActor(line_actor(link->GetOutputPort(), {0.25, 0.25, 0.3}, 6.0));
  }
  for (int i = 0; i < 3; ++i) {
    p.wheel[i] = vtkSmartPointer<vtkRegularPolygonSource>::New();
    p.wheel[i]->SetNumberOfSides(48);
    p.wheel[i]->SetRadius(p.radius);
    p.wheel_actor[i] = actor_of(p.wheel[i]->GetOutputPort(), {1.0, 1.0, 1.0});
    p.wheel_actor[i]->GetProperty()->SetLighting(false);
    p.renderer->AddActor(p.wheel_actor[i]);
  }
}

void PlanarRoverScene::add_text_and_camera() {
  Parts& p = *parts_;
  p.text = vtkSmartPointer<vtkTextActor>::New();
  p.text->GetTextProperty()->SetFontSize(16);
  p.text->GetTextProperty()->SetColor(0.05, 0.05, 0.1);
  p.text->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  p.text->GetPositionCoordinate()->SetValue(0.01, 0.9);
  p.renderer->AddViewProp(p.text);
  vtkCamera* cam = p.renderer->GetActiveCamera();
  cam->ParallelProjectionOn();
  cam->SetParallelScale(0.45);
}

vtkRenderer* PlanarRoverScene::renderer() const { return parts_->renderer; }

void PlanarRoverScene::attach(vtkRenderWindow* window) { window->AddRenderer(parts_->renderer); }

void PlanarRoverScene::detach(vtkRenderWindow* window) { window->RemoveRenderer(parts_->renderer); }

Eigen::Vector2d PlanarRoverScene::wheel_centre(int i) const { return parts_->centre[i]; }

void PlanarRoverScene::set_time(double t) {
  Parts& p = *parts_;
  const std::size_t k = p.pose->nearest_index(t), kw = p.wheels->nearest_index(t);
  const Eigen::Vector2d body(p.pose->channel("x").values[k], p.pose->channel("z").values[k]);
  const Eigen::Vector2d pivot(p.pose->channel("bogie_pivot_x").values[k], p.pose->channel("bogie_pivot_z").values[k]);
  for (int i = 0; i < 3; ++i) {
    const std::string n = std::to_string(i + 1);
    p.centre[i] = {p.wheels->channel("centre_x_" + n).values[kw], p.wheels->channel("centre_z_" + n).values[kw]};
    p.wheel[i]->SetCenter(p.centre[i].x(), p.centre[i].y(), 0.01);
    const double s = p.wheels->find_channel("slip_" + n) ? p.wheels->channel("slip_" + n).values[kw] : NAN;
    const Eigen::Vector3d c = slip_class_colour(std::isfinite(s) ? static_cast<int>(estimation::classify_slip(s)) : -1);
    p.wheel_actor[i]->GetProperty()->SetColor(c.x(), c.y(), c.z());
  }
  p.link[0]->SetPoint1(body.x(), body.y(), 0.005);
  p.link[0]->SetPoint2(p.centre[0].x(), p.centre[0].y(), 0.005);
  p.link[1]->SetPoint1(body.x(), body.y(), 0.005);
  p.link[1]->SetPoint2(pivot.x(), pivot.y(), 0.005);
  for (int i = 2; i < 4; ++i) {
    p.link[i]->SetPoint1(pivot.x(), pivot.y(), 0.005);
    p.link[i]->SetPoint2(p.centre[i - 1].x(), p.centre[i - 1].y(), 0.005);
  }
  show_text(t, k, kw);
  vtkCamera* cam = p.renderer->GetActiveCamera();
  cam->SetFocalPoint(body.x(), body.y() - 0.1, 0.0);
  cam->SetPosition(body.x(), body.y() - 0.1, 5.0);
  cam->SetViewUp(0, 1, 0);
  p.renderer->ResetCameraClippingRange();
}

void PlanarRoverScene::show_text(double t, std::size_t k, std::size_t kw) {
  Parts& p = *parts_;
  char line[256];
  int len = std::snprintf(line, sizeof line, "t = %.2f s   x = %.2f m   pitch %.1f deg   bogie %.1f deg", t,
                          p.pose->channel("x").values[k], p.pose->channel("pitch").values[k] * 180 / M_PI,
                          p.pose->channel("bogie_angle").values[k] * 180 / M_PI);
  for (int i = 0; i < 3; ++i) {
    const std::string n = std::to_string(i + 1);
    const double s = p.wheels->find_channel("slip_" + n) ? p.wheels->channel("slip_" + n).values[kw] : NAN;
    if (std::isfinite(s))
      len += std::snprintf(line + len, sizeof line - len, "%s slip %d: %.2f", i == 0 ? "\n" : "   ", i + 1, s);
  }
  p.text->SetInput(line);
}

}  // namespace roverlab::views
