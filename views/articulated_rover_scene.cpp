#include "views/articulated_rover_scene.h"

#include <vtkActor.h>
#include <vtkBillboardTextActor3D.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCubeSource.h>
#include <vtkCylinderSource.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkTransform.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/common/error.h"
#include "core/estimation/contact_angle/model_selection.h"
#include "core/estimation/contact_angle/streams.h"
#include "views/contact_angle_scene.h"
#include "views/vtk_parts.h"

namespace roverlab::views {

using Eigen::Vector3d;

namespace {

const Vector3d kSideSlipRgb(0.95, 0.55, 0.1);
const Vector3d kLinkRgb(0.25, 0.27, 0.32);
const Vector3d kBodyRgb(0.78, 0.8, 0.84);

// Frame origins along a wheel's chain, from g to its drive frame (Eq. 2.8).
// A DH origin on a joint's axis may lie far from the hardware (the bogie
// pivot's origin is on the rover's centre line): it is slid along the axis to
// the point nearest the next origin, where the arm is.
std::vector<Vector3d> chain_points(const kinematics::RoverModel& m, int wheel, const std::vector<double>& q) {
  kinematics::Mat4<double> X = kinematics::Mat4<double>::Identity();
  std::vector<Vector3d> points{Vector3d::Zero()};
  std::vector<std::pair<std::size_t, Vector3d>> on_axis;
  for (int li : m.wheels[static_cast<std::size_t>(wheel)].links) {
    const kinematics::DhLink& l = m.links[static_cast<std::size_t>(li)];
    if (l.joint >= 0) on_axis.emplace_back(points.size() - 1, X.block<3, 1>(0, 2));
    const double theta = l.theta + (l.joint >= 0 ? q[static_cast<std::size_t>(l.joint)] : 0.0);
    kinematics::append_dh<double>(X, theta, l.d, l.a, l.alpha);
    points.emplace_back(X.block<3, 1>(0, 3));
  }
  for (const auto& [i, axis] : on_axis) {
    if (i > 0) points[i] += (points[i + 1] - points[i]).dot(axis) * axis;
  }
  return points;
}

vtkSmartPointer<vtkActor> arrow_actor(const Vector3d& rgb, double radius_scale) {
  return unlit_arrow(rgb, 0.035 * radius_scale, 0.09 * radius_scale, 0.28, 12);
}

void set_lines(vtkActor* actor, const std::vector<Vector3d>& points) {
  vtkPolyDataMapper::SafeDownCast(actor->GetMapper())->SetInputData(polyline(points));
}

double value_at_sample(const log::Stream* s, const std::string& channel, std::size_t k) {
  const log::Channel* c = s != nullptr ? s->find_channel(channel) : nullptr;
  return c != nullptr ? c->values[k] : NAN;
}

}  // namespace

std::string articulated_rover_needs(const log::Log& lg, const kinematics::RoverModel* rover) {
  if (rover == nullptr || rover->wheels.empty()) return "the log's rover has no DH description (resources/rovers)";
  const log::Stream* joints = lg.find_stream("joints");
  if (joints == nullptr) return "no joints stream: the rover's configuration needs its joint angles";
  for (const auto& name : rover->joints) {
    if (joints->find_channel(name) == nullptr) return "stream joints has no channel '" + name + "'";
  }
  return {};
}

struct ArticulatedRoverScene::Parts {
  vtkSmartPointer<vtkRenderer> renderer = vtkSmartPointer<vtkRenderer>::New();
  vtkSmartPointer<vtkTextActor> text = vtkSmartPointer<vtkTextActor>::New();
  std::vector<vtkSmartPointer<vtkBillboardTextActor3D>> labels;  // FL .. FR beside each wheel
  std::vector<vtkSmartPointer<vtkActor>> wheels, links, estimate, truth, side_slip, sigma;
  vtkSmartPointer<vtkActor> ground[2];  // the strips under the left and the right wheels
  vtkSmartPointer<vtkCubeSource> base;  // the plane beneath them
  double extent = 1.0;
  const log::Stream* joints = nullptr;
  const log::Stream* estimate_stream = nullptr;
  const log::Stream* truth_stream = nullptr;
  const log::Stream* attitude = nullptr;
  Eigen::Matrix3d attitude_shown = Eigen::Matrix3d::Identity();  // body to level, at the time shown
};

ArticulatedRoverScene::ArticulatedRoverScene(const log::Log& lg, kinematics::RoverModel rover)
    : parts_(std::make_unique<Parts>()), rover_(std::move(rover)) {
  const std::string missing = articulated_rover_needs(lg, &rover_);
  if (!missing.empty()) throw DataError(missing);
  Parts& p = *parts_;
  p.joints = lg.find_stream("joints");
  p.estimate_stream = lg.find_stream(estimation::contact_streams::kWheels);
  p.truth_stream = lg.find_stream("truth/wheels");
  for (const char* source : {"truth/body", estimation::contact_streams::kBody}) {
    const log::Stream* s = lg.find_stream(source);
    if (p.attitude == nullptr && s != nullptr && s->find_channel("pitch") != nullptr) p.attitude = s;
  }
  t0_ = p.joints->start_time();
  t1_ = p.joints->end_time();
  if (p.estimate_stream == nullptr) {
    notes_.emplace_back("no contact-angle estimate in the log: run `roverlab estimate contact-angle` to draw it");
  }
  if (p.attitude == nullptr) notes_.emplace_back("no attitude in the log: the body is drawn level");

  const std::size_t n = rover_.wheels.size();
  const double r = rover_.wheel_radius;
  centres_.assign(n, Vector3d::Zero());
  ground_contacts_.assign(n, Vector3d::Zero());
  ground_tangents_.assign(n, Vector3d::UnitX());
  contacts_.assign(n, Vector3d::Zero());
  directions_.assign(n, Vector3d::Constant(NAN));
  p.renderer->SetBackground(0.93, 0.94, 0.97);
  p.renderer->SetBackground2(0.78, 0.82, 0.9);
  p.renderer->GradientBackgroundOn();
  for (std::size_t w = 0; w < n; ++w) {
    vtkNew<vtkCylinderSource> wheel;
    wheel->SetRadius(r);
    wheel->SetHeight(0.8 * r);
    wheel->SetResolution(32);
    p.wheels.push_back(actor_of(wheel->GetOutputPort(), Vector3d(0.6, 0.6, 0.62)));
    p.links.push_back(line_actor(polyline({Vector3d::Zero(), Vector3d::UnitX()}), kLinkRgb, 5.0));
    p.estimate.push_back(arrow_actor(Vector3d(ContactAngleScene::estimate_rgb[0], ContactAngleScene::estimate_rgb[1],
                                              ContactAngleScene::estimate_rgb[2]),
                                     1.3));
    p.truth.push_back(arrow_actor(
        Vector3d(ContactAngleScene::truth_rgb[0], ContactAngleScene::truth_rgb[1], ContactAngleScene::truth_rgb[2]),
        0.8));
    p.side_slip.push_back(arrow_actor(kSideSlipRgb, 0.9));
    p.labels.push_back(vtkSmartPointer<vtkBillboardTextActor3D>::New());
    p.labels.back()->SetInput(rover_.wheels[w].name.c_str());
    p.labels.back()->GetTextProperty()->SetFontSize(18);
    p.labels.back()->GetTextProperty()->SetBold(true);
    p.labels.back()->GetTextProperty()->SetColor(0.1, 0.1, 0.15);
    p.labels.back()->GetTextProperty()->SetJustificationToCentered();
    p.renderer->AddViewProp(p.labels.back());
    p.sigma.push_back(line_actor(polyline({Vector3d::Zero(), Vector3d::UnitX()}), Vector3d(0.12, 0.35, 0.85), 2.0));
    for (auto* a : {p.wheels.back().Get(), p.links.back().Get(), p.estimate.back().Get(), p.truth.back().Get(),
                    p.side_slip.back().Get(), p.sigma.back().Get()}) {
      p.renderer->AddActor(a);
    }
  }
  // Body: the box spanned by the frames hung from g, ground below the wheels at rest.
  const std::vector<double> rest(rover_.joints.size(), 0.0);
  Vector3d lo = Vector3d::Constant(1e9), hi = -lo, centre = Vector3d::Zero();
  double ground = 0.0;
  for (std::size_t w = 0; w < n; ++w) {
    const auto points = chain_points(rover_, static_cast<int>(w), rest);
    for (const auto& point : points) {
      lo = lo.cwiseMin(point);
      hi = hi.cwiseMax(point);
    }
    centre += points.back() / static_cast<double>(n);
    ground = std::min(ground, points.back().z() - r);
  }
  // Body: over the wheels, narrower than the track.
  vtkNew<vtkCubeSource> body;
  body->SetBounds(0.7 * lo.x(), 0.7 * hi.x(), 0.45 * lo.y(), 0.45 * hi.y(), -0.06, 0.06);
  p.renderer->AddActor(actor_of(body->GetOutputPort(), kBodyRgb));
  const double extent = std::max((hi - lo).norm(), 4.0 * r);
  p.extent = extent;
  p.base = vtkSmartPointer<vtkCubeSource>::New();
  p.base->SetBounds(centre.x() - 1.5 * extent, centre.x() + 1.5 * extent, centre.y() - 1.5 * extent,
                    centre.y() + 1.5 * extent, ground - 0.02, ground - 0.005);
  auto terrain_actor = actor_of(p.base->GetOutputPort(), Vector3d(0.74, 0.66, 0.53));
  terrain_actor->GetProperty()->SetOpacity(0.55);
  p.renderer->AddActor(terrain_actor);
  for (auto& strip : p.ground) {
    strip = actor_of(polyline({Vector3d::Zero(), Vector3d::UnitX()}), Vector3d(0.74, 0.62, 0.45));
    strip->GetProperty()->SetAmbient(0.45);  // lit from the camera, a level strip would be dark
    p.renderer->AddActor(strip);
  }
  p.text->GetTextProperty()->SetFontSize(16);
  p.text->GetTextProperty()->SetColor(0.05, 0.05, 0.1);
  p.text->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  p.text->GetPositionCoordinate()->SetValue(0.02, 0.02);
  p.renderer->AddViewProp(p.text);
  vtkCamera* cam = p.renderer->GetActiveCamera();
  cam->SetFocalPoint(centre.x(), centre.y(), 0.5 * (centre.z() + ground));
  cam->SetPosition(centre.x() + 0.9 * extent, centre.y() + 1.5 * extent, centre.z() + 0.9 * extent);
  cam->SetViewUp(0, 0, 1);
  cam->SetViewAngle(35.0);
  set_time(t0_);
}

ArticulatedRoverScene::~ArticulatedRoverScene() = default;

void ArticulatedRoverScene::attach(vtkRenderWindow* window) { window->AddRenderer(parts_->renderer); }

void ArticulatedRoverScene::detach(vtkRenderWindow* window) { window->RemoveRenderer(parts_->renderer); }

void ArticulatedRoverScene::set_time(double t) {
  Parts& p = *parts_;
  const std::size_t k = p.joints->nearest_index(t);
  std::vector<double> q;
  for (const auto& name : rover_.joints) q.push_back(p.joints->channel(name).values[k]);
  for (double& v : q) v = std::isfinite(v) ? v : 0.0;
  p.attitude_shown.setIdentity();
  if (p.attitude != nullptr) {  // roll and pitch only: the camera follows the heading
    const std::size_t ka = p.attitude->nearest_index(t);
    const double roll = value_at_sample(p.attitude, "roll", ka), pitch = value_at_sample(p.attitude, "pitch", ka);
    if (std::isfinite(roll) && std::isfinite(pitch)) {
      p.attitude_shown =
          (Eigen::AngleAxisd(pitch, Vector3d::UnitY()) * Eigen::AngleAxisd(roll, Vector3d::UnitX())).toRotationMatrix();
    }
  }
  const std::size_t ke = p.estimate_stream != nullptr ? p.estimate_stream->nearest_index(t) : 0;
  const std::size_t kt = p.truth_stream != nullptr ? p.truth_stream->nearest_index(t) : 0;
  for (std::size_t w = 0; w < rover_.wheels.size(); ++w) pose_wheel(w, q, ke, kt);
  place_ground();
  char line[480];
  // The estimates' model, as the estimator named it (chosen by the data, or set by hand and maybe rejected).
  const std::string model = p.estimate_stream != nullptr ? estimation::model_label(*p.estimate_stream) : "";
  // The key names only what is drawn: no side-slip arrow under model C, no truth in a field log.
  std::string key;
  const auto drawn = [](const std::vector<vtkSmartPointer<vtkActor>>& arrows) {
    return std::any_of(arrows.begin(), arrows.end(), [](const auto& a) { return a->GetVisibility() != 0; });
  };
  if (drawn(p.estimate)) key += "blue: velocity at the estimated contact angle   ";
  if (drawn(p.truth)) key += "green: truth   ";
  if (drawn(p.side_slip)) key += "orange: side slip";
  std::snprintf(line, sizeof line, "t = %.2f s   %s%s%s\n%s%swheels: grey at no slip, red at |slip| >= 0.5", t,
                rover_.name.c_str(), model.empty() ? "" : "   ", model.c_str(), key.c_str(), key.empty() ? "" : "\n");
  p.text->SetInput(line);
}

// One wheel at joint angles q: chain, wheel, and the arrows at its contact point.
void ArticulatedRoverScene::pose_wheel(std::size_t w, const std::vector<double>& q, std::size_t ke, std::size_t kt) {
  Parts& p = *parts_;
  const double r = rover_.wheel_radius;
  const int wheel = static_cast<int>(w);
  const std::string& name = rover_.wheels[w].name;
  const Eigen::Matrix3d& attitude = p.attitude_shown;
  std::vector<Vector3d> chain = chain_points(rover_, wheel, q);
  for (auto& point : chain) point = attitude * point;
  set_lines(p.links[w], chain);
  const auto pose = kinematics::wheel_pose<double>(rover_, wheel, q.data(), 0.0, 0.0, kinematics::WheelFrame::drive);
  const Eigen::Matrix3d R = attitude * pose.R;
  const Vector3d centre = attitude * pose.r;
  centres_[w] = centre;
  // The wheel's name above it, outboard.
  const Vector3d outboard = centre.y() >= 0.0 ? Vector3d(0, 0.9 * r, 1.6 * r) : Vector3d(0, -0.9 * r, 1.6 * r);
  const Vector3d label_at = centre + outboard;
  p.labels[w]->SetPosition(label_at.x(), label_at.y(), label_at.z());
  vtkNew<vtkMatrix4x4> m;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m->SetElement(i, j, R(i, j));
    m->SetElement(i, 3, centre[i]);
  }
  vtkNew<vtkTransform> placed;
  placed->SetMatrix(m);
  placed->RotateX(90.0);  // the cylinder's axis (y) onto the axle (the drive frame's z)
  p.wheels[w]->SetUserTransform(placed);

  // The wheel plane: forward f (the drive frame's x, pointing ahead) and up u.
  const Vector3d axle = R.col(2);
  Vector3d f = R.col(0);
  if (f.dot(attitude * Vector3d::UnitX()) < 0.0) f = -f;
  Vector3d u = axle.cross(f);
  if (u.z() < 0.0) u = -u;
  const double gamma = value_at_sample(p.estimate_stream, "contact_angle_" + name, ke);
  const double gamma_truth = value_at_sample(p.truth_stream, "contact_angle_" + name, kt);
  const double beta = value_at_sample(p.estimate_stream, "side_slip_" + name, ke);
  const double sigma = value_at_sample(p.estimate_stream, "contact_angle_" + name + "_sigma", ke);
  const double at = std::isfinite(gamma) ? gamma : std::isfinite(gamma_truth) ? gamma_truth : 0.0;
  // Seed 000 Fig. 5.1: the velocity at angle gamma above the wheel's forward
  // direction; the contact point lies at r along the normal to it.
  auto along = [&](double angle) { return Vector3d(std::cos(angle) * f + std::sin(angle) * u); };
  const Vector3d normal = -std::sin(at) * f + std::cos(at) * u;
  const Vector3d contact = centre - r * normal;
  contacts_[w] = contact;
  // The ground touches the wheel at the true contact angle when the log has it.
  const double at_ground = std::isfinite(gamma_truth) ? gamma_truth : at;
  ground_contacts_[w] = centre - r * (-std::sin(at_ground) * f + std::cos(at_ground) * u);
  ground_tangents_[w] = along(at_ground);
  const double length = 1.8 * r;
  p.estimate[w]->SetVisibility(std::isfinite(gamma));
  directions_[w] = std::isfinite(gamma) ? along(gamma) : Vector3d::Constant(NAN);
  if (std::isfinite(gamma)) place_arrow(p.estimate[w], contact, along(gamma), length);
  p.truth[w]->SetVisibility(std::isfinite(gamma_truth));
  if (std::isfinite(gamma_truth)) place_arrow(p.truth[w], contact, along(gamma_truth), 1.4 * r);
  p.side_slip[w]->SetVisibility(std::isfinite(beta) && std::isfinite(gamma));
  if (std::isfinite(beta) && std::isfinite(gamma)) {
    const Vector3d v = along(gamma);
    place_arrow(p.side_slip[w], contact, std::cos(beta) * v + std::sin(beta) * normal.cross(v), 1.3 * r);
  }
  p.sigma[w]->SetVisibility(std::isfinite(sigma) && std::isfinite(gamma));
  if (std::isfinite(sigma) && std::isfinite(gamma)) {
    std::vector<Vector3d> fan{contact};
    for (int i = 0; i <= 16; ++i) fan.emplace_back(contact + length * along(gamma - sigma + sigma * i / 8.0));
    fan.push_back(contact);
    set_lines(p.sigma[w], fan);
  }
  double slip = value_at_sample(p.estimate_stream, "slip_" + name, ke);
  if (!std::isfinite(slip)) slip = value_at_sample(p.truth_stream, "slip_" + name, kt);
  const double redness = std::isfinite(slip) ? std::min(std::abs(slip) / 0.5, 1.0) : 0.0;
  p.wheels[w]->GetProperty()->SetColor(0.6 + 0.3 * redness, 0.6 - 0.45 * redness, 0.62 - 0.45 * redness);
}

// Each side's strip: through each wheel's contact point, tangent there for a
// wheel radius either way, joined straight between wheels, carried on level
// for half the rover's size ahead and behind; the base plane just below.
void ArticulatedRoverScene::place_ground() {
  Parts& p = *parts_;
  const double r = rover_.wheel_radius, half_width = 0.9 * r, reach = 0.5 * p.extent;
  double lowest = std::numeric_limits<double>::infinity();
  for (int side = 0; side < 2; ++side) {
    std::vector<std::size_t> wheels;
    for (std::size_t w = 0; w < centres_.size(); ++w) {
      if ((centres_[w].y() >= 0.0) == (side == 0)) wheels.push_back(w);
    }
    std::sort(wheels.begin(), wheels.end(),
              [&](std::size_t a, std::size_t b) { return ground_contacts_[a].x() < ground_contacts_[b].x(); });
    std::vector<Vector3d> line;
    for (std::size_t w : wheels) {
      Vector3d t = ground_tangents_[w];
      if (t.x() < 0.0) t = -t;
      for (const double s : {-r, 0.0, r}) line.emplace_back(ground_contacts_[w] + s * t);
    }
    if (!line.empty()) {
      line.insert(line.begin(), line.front() - Vector3d(reach, 0.0, 0.0));
      line.emplace_back(line.back() + Vector3d(reach, 0.0, 0.0));
    }
    vtkNew<vtkPoints> points;
    vtkNew<vtkCellArray> strip;
    strip->InsertNextCell(static_cast<int>(2 * line.size()));
    for (const auto& c : line) {
      for (const double dy : {half_width, -half_width})
        strip->InsertCellPoint(points->InsertNextPoint(c.x(), c.y() + dy, c.z()));
      lowest = std::min(lowest, c.z());
    }
    vtkNew<vtkPolyData> data;
    data->SetPoints(points);
    data->SetStrips(strip);
    vtkPolyDataMapper::SafeDownCast(p.ground[side]->GetMapper())->SetInputData(data);
  }
  if (std::isfinite(lowest)) {
    double b[6];
    p.base->GetBounds(b);
    p.base->SetBounds(b[0], b[1], b[2], b[3], lowest - 0.02, lowest - 0.005);
  }
}

std::vector<std::vector<Vector3d>> ArticulatedRoverScene::ground_strips() const {
  std::vector<std::vector<Vector3d>> out;
  for (const auto& strip : parts_->ground) {
    vtkPolyData* data = vtkPolyData::SafeDownCast(strip->GetMapper()->GetInput());
    if (data == nullptr || data->GetPoints() == nullptr) continue;
    out.emplace_back();
    for (vtkIdType i = 0; i < data->GetNumberOfPoints(); ++i) {
      double x[3];
      data->GetPoint(i, x);
      out.back().emplace_back(x[0], x[1], x[2]);
    }
  }
  return out;
}

std::vector<double> ArticulatedRoverScene::base_plane_bounds() const {
  double b[6];
  parts_->base->GetBounds(b);
  return {b, b + 6};
}

std::string ArticulatedRoverScene::caption() const { return parts_->text->GetInput(); }

std::vector<std::pair<std::string, Eigen::Vector3d>> ArticulatedRoverScene::wheel_labels() const {
  std::vector<std::pair<std::string, Eigen::Vector3d>> out;
  for (const auto& label : parts_->labels) {
    const double* at = label->GetPosition();
    out.emplace_back(label->GetInput(), Eigen::Vector3d(at[0], at[1], at[2]));
  }
  return out;
}

}  // namespace roverlab::views
