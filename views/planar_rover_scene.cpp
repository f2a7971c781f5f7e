#include "views/planar_rover_scene.h"

#include <vtkActor.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCubeSource.h>
#include <vtkCylinderSource.h>
#include <vtkLineSource.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "core/common/error.h"
#include "core/estimation/net_traction/streams.h"
#include "core/models/slip.h"
#include "views/contact_angle_scene.h"
#include "views/rover_scene.h"
#include "views/vtk_parts.h"

namespace roverlab::views {

bool is_planar_rocker_bogie_log(const log::Log& lg) {
  const log::Stream* p = lg.find_stream("truth/pose");
  const log::Stream* w = lg.find_stream("truth/wheels");
  return p && w && p->find_channel("bogie_pivot_x") && p->find_channel("x") && w->find_channel("centre_x_1") &&
         w->find_channel("centre_z_3") && p->size() >= 2;
}

std::string planar_rover_needs(const log::Log& lg) {
  const log::Stream* p = lg.find_stream("truth/pose");
  if (p == nullptr) return "no truth/pose stream";
  for (const char* c : {"x", "z", "pitch"}) {
    const log::Channel* ch = p->find_channel(c);
    if (ch == nullptr) continue;
    if (std::none_of(ch->values.begin(), ch->values.end(), [](double v) { return std::isfinite(v); })) {
      return std::string("truth/pose channel '") + c + "' has no finite value: no rover to draw";
    }
  }
  return "";
}

// Side s (0: left, +y; 1: right, mirrored) of the 3D rover.
struct PlanarRoverScene::Parts {
  vtkSmartPointer<vtkRenderer> renderer;
  vtkSmartPointer<vtkActor> wheel_actor[2][3];
  // Per side: body->wheel 1, body->bogie pivot, pivot->wheel 2, pivot->wheel 3.
  vtkSmartPointer<vtkLineSource> link[2][4];
  vtkSmartPointer<vtkLineSource> axle;  // between the two rocker pivots
  vtkSmartPointer<vtkActor> body;
  vtkSmartPointer<vtkTextActor> text;
  // Contact arrows per side and wheel: estimate, its 1-sigma fan, truth.
  vtkSmartPointer<vtkActor> estimate[2][3], sigma[2][3], truth[2][3];
  Eigen::Vector2d direction[2][3];  // [truth][wheel]
  const log::Stream* pose = nullptr;
  const log::Stream* wheels = nullptr;
  const log::Stream* estimates = nullptr;
  double radius = 0.075, track = 0.5, width = 0.06, wheelbase = 0.5;
  Eigen::Vector2d centre[3];
  double side_y(int side) const { return side == 0 ? 0.5 * track : -0.5 * track; }
};

PlanarRoverScene::PlanarRoverScene(const log::Log& lg) {
  if (!is_planar_rocker_bogie_log(lg))
    throw DataError("not a planar rocker-bogie log (truth/pose and truth/wheels with positions)");
  parts_ = std::make_unique<Parts>();
  Parts& p = *parts_;
  p.pose = lg.find_stream("truth/pose");
  p.wheels = lg.find_stream("truth/wheels");
  p.estimates = lg.find_stream(estimation::net_traction_streams::kWheels);
  if (p.estimates == nullptr)
    notes_.emplace_back(
        "no net-traction estimate in the log: run `roverlab estimate net-traction` to draw the estimated contact "
        "angles");
  const auto r = lg.metadata.extra.find("truth/wheel_radius_m");
  if (r != lg.metadata.extra.end()) p.radius = std::stod(r->second);
  t0_ = p.pose->start_time();
  t1_ = p.pose->end_time();
  // Track: the wheelbase at the start (the planar model has none); wheels 0.8 radius wide.
  const auto& x1 = p.wheels->channel("centre_x_1").values;
  const auto& x3 = p.wheels->channel("centre_x_3").values;
  p.wheelbase = std::isfinite(x1[0] - x3[0]) && std::abs(x1[0] - x3[0]) > 1e-3 ? std::abs(x1[0] - x3[0]) : 0.5;
  p.track = p.wheelbase;
  p.width = 0.8 * p.radius;
  p.renderer = vtkSmartPointer<vtkRenderer>::New();
  p.renderer->SetBackground(0.95, 0.96, 0.98);
  add_terrain();
  add_links_and_wheels();
  add_contact_arrows();
  add_text_and_camera();
  set_time(t0_);
}

PlanarRoverScene::~PlanarRoverScene() = default;

// Terrain: the wheel centres' tracks, a wheel radius lower, sorted along x,
// extruded across the track as a surface.
void PlanarRoverScene::add_terrain() {
  Parts& p = *parts_;
  std::map<double, double> profile;
  for (int i = 1; i <= 3; ++i) {
    const auto& xs = p.wheels->channel("centre_x_" + std::to_string(i)).values;
    const auto& zs = p.wheels->channel("centre_z_" + std::to_string(i)).values;
    for (std::size_t k = 0; k < xs.size(); ++k) {
      if (std::isfinite(xs[k]) && std::isfinite(zs[k])) profile[std::round(xs[k] * 1000.0) / 1000.0] = zs[k] - p.radius;
    }
  }
  const double half = 0.5 * p.track + 1.5 * p.width;
  vtkNew<vtkPoints> points;
  vtkNew<vtkCellArray> quads;
  vtkIdType n = 0;
  for (const auto& [x, z] : profile) {
    points->InsertNextPoint(x, -half, z);
    points->InsertNextPoint(x, half, z);
    if (n > 0) {
      const vtkIdType q[4] = {2 * (n - 1), 2 * n, 2 * n + 1, 2 * (n - 1) + 1};
      quads->InsertNextCell(4, q);
    }
    ++n;
  }
  vtkNew<vtkPolyData> surface;
  surface->SetPoints(points);
  surface->SetPolys(quads);
  vtkSmartPointer<vtkActor> ground = actor_of(surface.GetPointer(), {0.55, 0.45, 0.3});
  ground->GetProperty()->SetLighting(false);  // the terrain's colour as it is, whatever the view
  p.renderer->AddActor(ground);
  // The profile's edge on both sides, darker: the relief reads at any angle.
  for (double y : {-half, half}) {
    std::vector<Eigen::Vector3d> edge;
    edge.reserve(profile.size());
    for (const auto& [x, z] : profile) edge.emplace_back(x, y, z + 0.002);
    p.renderer->AddActor(line_actor(polyline(edge), {0.35, 0.27, 0.17}, 2.0));
  }
}

// Both sides' rocker and bogie links and wheels (cylinders along y), the
// axle between the rocker pivots and the body box.
void PlanarRoverScene::add_links_and_wheels() {
  Parts& p = *parts_;
  vtkNew<vtkCylinderSource> wheel;  // its axis is y: the wheels' axle
  wheel->SetRadius(p.radius);
  wheel->SetHeight(p.width);
  wheel->SetResolution(40);
  for (int side = 0; side < 2; ++side) {
    for (auto& link : p.link[side]) {
      link = vtkSmartPointer<vtkLineSource>::New();
      p.renderer->AddActor(line_actor(link->GetOutputPort(), {0.25, 0.25, 0.3}, 6.0));
    }
    for (int i = 0; i < 3; ++i) {
      p.wheel_actor[side][i] = actor_of(wheel->GetOutputPort(), {1.0, 1.0, 1.0});
      p.wheel_actor[side][i]->GetProperty()->SetLighting(false);  // the slip class's colour as it is
      p.renderer->AddActor(p.wheel_actor[side][i]);
    }
  }
  p.axle = vtkSmartPointer<vtkLineSource>::New();
  p.renderer->AddActor(line_actor(p.axle->GetOutputPort(), {0.25, 0.25, 0.3}, 5.0));
  vtkNew<vtkCubeSource> box;
  box->SetXLength(0.5 * p.wheelbase);
  box->SetYLength(std::max(0.1, p.track - 2.0 * p.width));
  box->SetZLength(0.15 * p.wheelbase);
  p.body = actor_of(box->GetOutputPort(), {0.72, 0.74, 0.8});
  p.renderer->AddActor(p.body);
}

void PlanarRoverScene::add_contact_arrows() {
  Parts& p = *parts_;
  const Eigen::Vector3d blue(ContactAngleScene::estimate_rgb[0], ContactAngleScene::estimate_rgb[1],
                             ContactAngleScene::estimate_rgb[2]);
  const Eigen::Vector3d green(ContactAngleScene::truth_rgb[0], ContactAngleScene::truth_rgb[1],
                              ContactAngleScene::truth_rgb[2]);
  for (int side = 0; side < 2; ++side) {
    for (int i = 0; i < 3; ++i) {
      p.estimate[side][i] = unlit_arrow(blue, 0.045, 0.12, 0.28, 12);
      p.truth[side][i] = unlit_arrow(green, 0.03, 0.08, 0.28, 12);
      p.sigma[side][i] = line_actor(polyline({Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX()}), blue, 2.0);
      for (auto* a : {p.estimate[side][i].Get(), p.truth[side][i].Get(), p.sigma[side][i].Get()})
        p.renderer->AddActor(a);
    }
  }
}

namespace {

double value_at_time(const log::Stream* s, const std::string& channel, double t) {
  const log::Channel* c = s != nullptr ? s->find_channel(channel) : nullptr;
  return c != nullptr ? c->values[s->nearest_index(t)] : NAN;
}

}  // namespace

// Seed 003 Eq. 4.40: the path's direction at the contact angle gamma,
// (cos gamma, sin gamma) in (x, z); the contact point a radius below the
// centre along the normal to it, on the outer face of each side's wheel.
void PlanarRoverScene::place_contact_arrows(double t) {
  Parts& p = *parts_;
  const auto along = [](double angle) { return Eigen::Vector2d(std::cos(angle), std::sin(angle)); };
  for (int i = 0; i < 3; ++i) {
    const std::string n = std::to_string(i + 1);
    const double gamma = value_at_time(p.estimates, "contact_angle_" + n, t);
    const double sigma = value_at_time(p.estimates, "contact_angle_sigma_" + n, t);
    const double gamma_truth = value_at_time(p.wheels, "contact_angle_" + n, t);
    p.direction[0][i] = std::isfinite(gamma) ? along(gamma) : Eigen::Vector2d::Constant(NAN);
    p.direction[1][i] = std::isfinite(gamma_truth) ? along(gamma_truth) : Eigen::Vector2d::Constant(NAN);
    const double at = std::isfinite(gamma) ? gamma : std::isfinite(gamma_truth) ? gamma_truth : 0.0;
    const Eigen::Vector2d contact = p.centre[i] - p.radius * Eigen::Vector2d(-std::sin(at), std::cos(at));
    const double length = 2.2 * p.radius;
    for (int side = 0; side < 2; ++side) {
      const double y = p.side_y(side) + (side == 0 ? 1.0 : -1.0) * (0.5 * p.width + 0.01);
      const auto in_3d = [y](const Eigen::Vector2d& v) { return Eigen::Vector3d(v.x(), y, v.y()); };
      const auto point = [&](double angle, double l) { return in_3d(contact + l * along(angle)); };
      const bool estimated = std::isfinite(gamma);
      p.estimate[side][i]->SetVisibility(estimated);
      if (estimated) place_arrow(p.estimate[side][i], in_3d(contact), point(gamma, 1.0) - in_3d(contact), length);
      p.truth[side][i]->SetVisibility(std::isfinite(gamma_truth));
      // The truth a little further out, so that an estimate on it does not hide it.
      const Eigen::Vector3d out(0.0, side == 0 ? 0.02 : -0.02, 0.0);
      if (std::isfinite(gamma_truth))
        place_arrow(p.truth[side][i], in_3d(contact) + out, point(gamma_truth, 1.0) - in_3d(contact), 1.6 * p.radius);
      const bool fan = estimated && std::isfinite(sigma);
      p.sigma[side][i]->SetVisibility(fan);
      if (fan) {
        std::vector<Eigen::Vector3d> points{in_3d(contact)};
        for (int j = 0; j <= 16; ++j) points.push_back(point(gamma - sigma + sigma * j / 8.0, length));
        points.push_back(in_3d(contact));
        vtkPolyDataMapper::SafeDownCast(p.sigma[side][i]->GetMapper())->SetInputData(polyline(points));
      }
    }
  }
}

Eigen::Vector2d PlanarRoverScene::contact_direction(int i, bool truth) const {
  return parts_->direction[truth ? 1 : 0][i];
}

void PlanarRoverScene::add_text_and_camera() {
  Parts& p = *parts_;
  p.text = vtkSmartPointer<vtkTextActor>::New();
  p.text->GetTextProperty()->SetFontSize(16);
  p.text->GetTextProperty()->SetColor(0.05, 0.05, 0.1);
  p.text->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  p.text->GetPositionCoordinate()->SetValue(0.01, 0.9);
  p.renderer->AddViewProp(p.text);
  p.renderer->GetActiveCamera()->SetViewAngle(30.0);
}

vtkRenderer* PlanarRoverScene::renderer() const { return parts_->renderer; }

void PlanarRoverScene::attach(vtkRenderWindow* window) { window->AddRenderer(parts_->renderer); }

void PlanarRoverScene::detach(vtkRenderWindow* window) { window->RemoveRenderer(parts_->renderer); }

Eigen::Vector2d PlanarRoverScene::wheel_centre(int i) const { return parts_->centre[i]; }

double PlanarRoverScene::track() const { return parts_->track; }

double PlanarRoverScene::wheel_width() const { return parts_->width; }

void PlanarRoverScene::set_time(double t) {
  Parts& p = *parts_;
  const std::size_t k = p.pose->nearest_index(t), kw = p.wheels->nearest_index(t);
  const Eigen::Vector2d body(p.pose->channel("x").values[k], p.pose->channel("z").values[k]);
  const Eigen::Vector2d pivot(p.pose->channel("bogie_pivot_x").values[k], p.pose->channel("bogie_pivot_z").values[k]);
  for (int i = 0; i < 3; ++i) {
    const std::string n = std::to_string(i + 1);
    p.centre[i] = {p.wheels->channel("centre_x_" + n).values[kw], p.wheels->channel("centre_z_" + n).values[kw]};
    const double s = p.wheels->find_channel("slip_" + n) ? p.wheels->channel("slip_" + n).values[kw] : NAN;
    const Eigen::Vector3d c = slip_class_colour(std::isfinite(s) ? static_cast<int>(estimation::classify_slip(s)) : -1);
    for (int side = 0; side < 2; ++side) {
      p.wheel_actor[side][i]->SetPosition(p.centre[i].x(), p.side_y(side), p.centre[i].y());
      p.wheel_actor[side][i]->GetProperty()->SetColor(c.x(), c.y(), c.z());
    }
  }
  // The links run inside the wheels (half a wheel width nearer the body).
  for (int side = 0; side < 2; ++side) {
    const double y = p.side_y(side) + (side == 0 ? -1.0 : 1.0) * p.width;
    const auto at = [y](const Eigen::Vector2d& v) { return Eigen::Vector3d(v.x(), y, v.y()); };
    const std::pair<Eigen::Vector2d, Eigen::Vector2d> ends[4] = {
        {body, p.centre[0]}, {body, pivot}, {pivot, p.centre[1]}, {pivot, p.centre[2]}};
    for (int l = 0; l < 4; ++l) {
      p.link[side][l]->SetPoint1(at(ends[l].first).data());
      p.link[side][l]->SetPoint2(at(ends[l].second).data());
    }
  }
  const double pitch = p.pose->channel("pitch").values[k];
  p.axle->SetPoint1(body.x(), p.side_y(0) - p.width, body.y());
  p.axle->SetPoint2(body.x(), p.side_y(1) + p.width, body.y());
  p.body->SetPosition(body.x(), 0.0, body.y() + 0.05 * p.wheelbase);
  p.body->SetOrientation(0.0, std::isfinite(pitch) ? -pitch * 180.0 / M_PI : 0.0, 0.0);
  place_contact_arrows(t);
  show_text(t, k, kw);
  // Obliquely from the front left, above, following the body.
  const double d = 3.6 * p.wheelbase;
  vtkCamera* cam = p.renderer->GetActiveCamera();
  cam->SetFocalPoint(body.x(), 0.0, body.y() - 0.15 * p.wheelbase);
  cam->SetPosition(body.x() + 0.5 * d, 0.9 * d, body.y() + 0.45 * d);
  cam->SetViewUp(0, 0, 1);
  p.renderer->ResetCameraClippingRange();
}

void PlanarRoverScene::show_text(double t, std::size_t k, std::size_t kw) {
  Parts& p = *parts_;
  char line[512];
  int len = std::snprintf(line, sizeof line, "t = %.2f s   x = %.2f m   pitch %.1f deg   bogie %.1f deg", t,
                          p.pose->channel("x").values[k], p.pose->channel("pitch").values[k] * 180 / M_PI,
                          p.pose->channel("bogie_angle").values[k] * 180 / M_PI);
  for (int i = 0; i < 3; ++i) {
    const std::string n = std::to_string(i + 1);
    const double s = p.wheels->find_channel("slip_" + n) ? p.wheels->channel("slip_" + n).values[kw] : NAN;
    if (std::isfinite(s))
      len += std::snprintf(line + len, sizeof line - len, "%s slip %d: %.2f", i == 0 ? "\n" : "   ", i + 1, s);
  }
  std::snprintf(line + len, sizeof line - len, "\ncontact-angle arrows: %sgreen truth",
                p.estimates != nullptr ? "blue estimate (1-sigma fan), " : "");
  p.text->SetInput(line);
}

}  // namespace roverlab::views
