#include "views/rover_scene.h"
#include "core/estimation/contact_angle/streams.h"
#include "core/estimation/net_traction/streams.h"

#include <vtkActor.h>
#include <vtkArrowSource.h>
#include <vtkCamera.h>
#include <vtkCubeSource.h>
#include <vtkCylinderSource.h>
#include <vtkLegendBoxActor.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPlaneSource.h>
#include <vtkPolyData.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkTransform.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/estimation/ins_slip/streams.h"
#include "core/log/stream.h"
#include "core/models/slip.h"
#include "views/articulated_rover_scene.h"
#include "views/planar_rover_scene.h"
#include "views/vtk_parts.h"

namespace roverlab::views {

namespace {

std::vector<double> unwrap(std::vector<double> a) {
  for (std::size_t i = 1; i < a.size(); ++i) {
    a[i] = a[i - 1] + std::remainder(a[i] - a[i - 1], 2.0 * M_PI);
  }
  return a;
}

const std::vector<double>* channel(const log::Stream& s, const char* name) {
  const auto* c = s.find_channel(name);
  return c ? &c->values : nullptr;
}

// A pose track on the ground at height z (its finite points).
vtkSmartPointer<vtkActor> track_actor(const PoseTrack& tr, const Eigen::Vector3d& colour, double z) {
  std::vector<Eigen::Vector3d> points;
  for (std::size_t i = 0; i < tr.time.size(); ++i) {
    if (std::isfinite(tr.east[i] + tr.north[i])) points.emplace_back(tr.east[i], tr.north[i], z);
  }
  return line_actor(polyline(points), colour, 3.0);
}

// Body (forward-right-down) to world (east-north-up) at a pose.
vtkSmartPointer<vtkMatrix4x4> pose_matrix(const PoseTrack::Pose& p, double z) {
  const double cr = std::cos(p.roll), sr = std::sin(p.roll), cp = std::cos(p.pitch), sp = std::sin(p.pitch),
               cy = std::cos(p.yaw), sy = std::sin(p.yaw);
  Eigen::Matrix3d C;  // body -> NED, Rz(yaw) Ry(pitch) Rx(roll)
  C << cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr, sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr,
      -sp, cp * sr, cp * cr;
  Eigen::Matrix3d ned_to_enu;
  ned_to_enu << 0, 1, 0, 1, 0, 0, 0, 0, -1;
  const Eigen::Matrix3d R = ned_to_enu * C;
  vtkNew<vtkMatrix4x4> m;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m->SetElement(i, j, R(i, j));
  }
  m->SetElement(0, 3, p.east);
  m->SetElement(1, 3, p.north);
  m->SetElement(2, 3, z);
  return vtkSmartPointer<vtkMatrix4x4>(m);
}

struct RoverModel {
  std::vector<vtkSmartPointer<vtkActor>> parts;  // body, 4 wheels, arrow
  std::vector<vtkSmartPointer<vtkActor>> wheels;
  vtkSmartPointer<vtkActor> arrow;
};

RoverModel make_rover(const estimation::SkidSteerGeometry& g, double opacity) {
  RoverModel m;
  vtkNew<vtkCubeSource> body;
  body->SetXLength(g.wheelbase + 0.25);
  body->SetYLength(std::max(0.1, g.track - 0.16));
  body->SetZLength(0.18);
  body->SetCenter(0.0, 0.0, -0.05);  // body frame: z down, origin at axle height
  auto b = actor_of(body->GetOutputPort(), RoverScene::body_colour());
  b->GetProperty()->SetOpacity(opacity);
  m.parts.push_back(b);
  for (int side : {-1, 1}) {
    for (int end : {-1, 1}) {
      vtkNew<vtkCylinderSource> w;  // axis along y: the body's lateral axis
      w->SetRadius(g.wheel_radius);
      w->SetHeight(0.1);
      w->SetResolution(32);
      w->SetCenter(0.5 * end * g.wheelbase, 0.5 * side * g.track, 0.0);
      auto a = actor_of(w->GetOutputPort(), {0.5, 0.5, 0.5});
      a->GetProperty()->SetOpacity(opacity);
      m.wheels.push_back(a);
      m.parts.push_back(a);
    }
  }
  vtkNew<vtkArrowSource> arrow;
  arrow->SetTipResolution(24);
  arrow->SetShaftResolution(24);
  m.arrow = actor_of(arrow->GetOutputPort(), {0.1, 0.3, 0.9});
  m.arrow->GetProperty()->SetOpacity(opacity);
  m.parts.push_back(m.arrow);
  return m;
}

// Poses a rover model; the arrow along the body's forward axis, above the
// body, its length the speed.
void place(RoverModel& m, const PoseTrack::Pose& q, double z, double speed) {
  auto matrix = pose_matrix(q, z);
  for (auto& a : m.parts) a->SetUserMatrix(matrix);
  vtkNew<vtkTransform> arrow;
  arrow->SetMatrix(matrix);
  arrow->Translate(0.0, 0.0, -0.35);
  const double len = std::max(0.05, 1.5 * std::abs(speed));
  arrow->Scale(speed < 0 ? -len : len, 0.6, 0.6);
  m.arrow->SetUserMatrix(arrow->GetMatrix());
  m.arrow->SetVisibility(std::abs(speed) > 0.02);
}

Eigen::Vector3d track_colour(const std::string& source) {
  if (source == estimation::ins_streams::kPose) return {0.12, 0.35, 0.85};
  if (source == "truth/motion") return {0.1, 0.6, 0.2};
  if (source == estimation::ins_streams::kOdometryPose) return {0.95, 0.55, 0.1};
  return {0.15, 0.15, 0.15};  // gps
}

}  // namespace

PoseTrack::Pose PoseTrack::at(double t) const {
  Pose p;
  if (time.empty()) return p;
  const double tc = std::clamp(t, time.front(), time.back());
  p.east = log::interpolate_linear(time, east, tc);
  p.north = log::interpolate_linear(time, north, tc);
  p.roll = log::interpolate_linear(time, roll, tc);
  p.pitch = log::interpolate_linear(time, pitch, tc);
  p.yaw = log::interpolate_linear(time, yaw, tc);
  return p;
}

namespace {

// The pose sources, best first: stream, its yaw channel (none: the course
// over ground), whether it holds roll and pitch.
struct PoseSource {
  const char* stream;
  const char* yaw;
  bool attitude;
};
constexpr PoseSource kPoseSources[] = {{estimation::ins_streams::kPose, "yaw", true},
                                       {"truth/motion", "yaw", false},
                                       {estimation::ins_streams::kOdometryPose, "heading", false},
                                       {"gps", nullptr, false}};

const log::Stream* pose_stream(const log::Log& lg, const PoseSource& source) {
  const log::Stream* s = lg.find_stream(source.stream);
  if (s == nullptr || s->size() < 2 || channel(*s, "east") == nullptr || channel(*s, "north") == nullptr)
    return nullptr;
  return s;
}

// Course over ground, held through stops.
std::vector<double> course(const PoseTrack& tr) {
  const std::size_t k = tr.time.size();
  std::vector<double> yaw(k, 0.0);
  double last = 0.0;
  for (std::size_t i = 0; i < k; ++i) {
    const std::size_t a = i > 5 ? i - 5 : 0, b = std::min(k - 1, i + 5);
    const double de = tr.east[b] - tr.east[a], dn = tr.north[b] - tr.north[a];
    if (std::hypot(de, dn) > 0.2) last = std::atan2(de, dn);
    yaw[i] = last;
  }
  return unwrap(yaw);
}

PoseTrack track_of(const log::Stream& s, const PoseSource& source) {
  PoseTrack tr;
  tr.source = source.stream;
  tr.time = s.time();
  tr.east = *channel(s, "east");
  tr.north = *channel(s, "north");
  const std::size_t k = tr.time.size();
  tr.roll.assign(k, 0.0);
  tr.pitch.assign(k, 0.0);
  if (source.attitude && channel(s, "roll") && channel(s, "pitch")) {
    tr.roll = *channel(s, "roll");
    tr.pitch = *channel(s, "pitch");
  }
  if (source.yaw != nullptr && channel(s, source.yaw) != nullptr) {
    tr.yaw = unwrap(*channel(s, source.yaw));
  } else {
    tr.yaw = course(tr);
  }
  return tr;
}

}  // namespace

std::vector<PoseTrack> pose_tracks(const log::Log& lg) {
  std::vector<PoseTrack> out;
  for (const auto& source : kPoseSources) {
    if (const log::Stream* s = pose_stream(lg, source)) out.push_back(track_of(*s, source));
  }
  return out;
}

std::string pose_track_needs(const log::Log& lg) {
  for (const auto& source : kPoseSources) {
    if (pose_stream(lg, source) != nullptr) return {};
  }
  return "no pose: the log has none of estimate/ins/pose, truth/motion, estimate/odometry/pose, gps";
}

Eigen::Vector3d slip_class_colour(int c) {
  switch (c) {
    case 0:
      return {0.20, 0.70, 0.30};
    case 1:
      return {0.65, 0.80, 0.20};
    case 2:
      return {0.95, 0.80, 0.15};
    case 3:
      return {0.95, 0.50, 0.10};
    case 4:
      return {0.85, 0.15, 0.10};
    default:
      return {0.5, 0.5, 0.5};
  }
}

struct RoverScene::Parts {
  vtkSmartPointer<vtkRenderer> renderer;
  RoverModel rover, ghost;
  bool has_ghost = false;
  vtkSmartPointer<vtkTextActor> text;
  const log::Stream* slip = nullptr;  // estimate/ins/slip
  const log::Stream* truth_slip = nullptr;
  estimation::SkidSteerGeometry geometry;
};

RoverScene::RoverScene(const log::Log& lg, const estimation::SkidSteerGeometry& g) : parts_(std::make_unique<Parts>()) {
  parts_->geometry = g;
  parts_->renderer = vtkSmartPointer<vtkRenderer>::New();
  parts_->renderer->SetBackground(0.80, 0.86, 0.93);
  parts_->renderer->SetBackground2(0.97, 0.98, 1.0);
  parts_->renderer->GradientBackgroundOn();
  read_log(lg);
  add_ground();
  add_tracks();
  add_rovers();
  add_text();
  set_time(start_);
}

RoverScene::~RoverScene() = default;

// The pose tracks, the slip streams and the notes on what is missing.
void RoverScene::read_log(const log::Log& lg) {
  Parts& p = *parts_;
  tracks_ = pose_tracks(lg);
  if (tracks_.empty()) {
    notes_.emplace_back(pose_track_needs(lg));
  } else {
    pose_source_ = tracks_.front().source;
    start_ = tracks_.front().time.front();
    end_ = tracks_.front().time.back();
    if (pose_source_ == "gps" || pose_source_ == estimation::ins_streams::kOdometryPose) {
      notes_.emplace_back("no attitude: roll and pitch are drawn level (run `roverlab estimate ins-slip`)");
    }
  }
  p.slip = lg.find_stream(estimation::ins_streams::kSlip);
  if (p.slip != nullptr && p.slip->find_channel("slip_class") == nullptr) p.slip = nullptr;
  p.truth_slip = lg.find_stream("truth/slip");
  if (p.truth_slip != nullptr && p.truth_slip->find_channel("slip_ratio") == nullptr) p.truth_slip = nullptr;
  if (p.slip == nullptr) notes_.emplace_back("no slip estimate: wheels are grey");
  notes_.emplace_back("no contact-angle or side-slip estimates for this rover (seed 000 estimator)");
}

// A ground plane 5 m beyond every track, with a 2 m grid.
void RoverScene::add_ground() {
  double e0 = -5, e1 = 5, n0 = -5, n1 = 5;
  for (const auto& tr : tracks_) {
    for (std::size_t i = 0; i < tr.time.size(); ++i) {
      if (!std::isfinite(tr.east[i] + tr.north[i])) continue;
      e0 = std::min(e0, tr.east[i] - 5);
      e1 = std::max(e1, tr.east[i] + 5);
      n0 = std::min(n0, tr.north[i] - 5);
      n1 = std::max(n1, tr.north[i] + 5);
    }
  }
  vtkNew<vtkPlaneSource> plane;
  plane->SetOrigin(e0, n0, 0.0);
  plane->SetPoint1(e1, n0, 0.0);
  plane->SetPoint2(e0, n1, 0.0);
  plane->SetResolution(static_cast<int>((e1 - e0) / 2), static_cast<int>((n1 - n0) / 2));
  auto ground = actor_of(plane->GetOutputPort(), {0.80, 0.74, 0.62});
  ground->GetProperty()->SetAmbient(0.45);
  ground->GetProperty()->SetDiffuse(0.6);
  parts_->renderer->AddActor(ground);
  auto grid = actor_of(plane->GetOutputPort(), {0.62, 0.56, 0.47});
  grid->GetProperty()->SetRepresentationToWireframe();
  grid->GetProperty()->SetLighting(false);
  parts_->renderer->AddActor(grid);
}

// Every pose track on the ground, and a legend naming them.
void RoverScene::add_tracks() {
  vtkNew<vtkLegendBoxActor> legend;
  legend->SetNumberOfEntries(static_cast<int>(tracks_.size()));
  // Legend symbol: a colour swatch (a line at the symbol box's foot read as "_" before each name).
  const auto symbol = legend_swatch();
  legend_symbol_ = symbol;
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    const Eigen::Vector3d c = track_colour(tracks_[i].source);
    parts_->renderer->AddActor(track_actor(tracks_[i], c, 0.01 + 0.002 * static_cast<double>(i)));
    double rgb[3] = {c.x(), c.y(), c.z()};
    legend->SetEntry(static_cast<int>(i), symbol, tracks_[i].source.c_str(), rgb);
    legend_entries_.push_back(tracks_[i].source);
  }
  legend->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  legend->GetPositionCoordinate()->SetValue(0.01, 0.01);
  legend->GetPosition2Coordinate()->SetValue(0.28, 0.04 + 0.04 * static_cast<double>(tracks_.size()));
  legend->UseBackgroundOn();
  legend->SetBackgroundColor(1, 1, 1);
  legend->SetBackgroundOpacity(0.7);
  if (!tracks_.empty()) parts_->renderer->AddViewProp(legend);
}

// The rover, and truth beside the estimate as a green ghost rover.
void RoverScene::add_rovers() {
  Parts& p = *parts_;
  p.rover = make_rover(p.geometry, 1.0);
  for (auto& a : p.rover.parts) p.renderer->AddActor(a);
  if (tracks_.size() > 1 && tracks_[1].source == "truth/motion" && pose_source_ != "truth/motion") {
    p.ghost = make_rover(p.geometry, 0.35);
    p.has_ghost = true;
    for (auto& a : p.ghost.parts) {
      a->GetProperty()->SetColor(0.1, 0.6, 0.2);
      p.renderer->AddActor(a);
    }
  }
}

void RoverScene::add_text() {
  Parts& p = *parts_;
  p.text = vtkSmartPointer<vtkTextActor>::New();
  p.text->GetTextProperty()->SetFontSize(16);
  p.text->GetTextProperty()->SetColor(0.05, 0.05, 0.1);
  p.text->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  p.text->GetPositionCoordinate()->SetValue(0.01, 0.90);
  p.renderer->AddViewProp(p.text);
}

vtkRenderer* RoverScene::renderer() const { return parts_->renderer; }

vtkPolyData* RoverScene::legend_symbol() const { return legend_symbol_; }

void RoverScene::attach(vtkRenderWindow* window) { window->AddRenderer(parts_->renderer); }

void RoverScene::detach(vtkRenderWindow* window) { window->RemoveRenderer(parts_->renderer); }

void RoverScene::set_time(double t) {
  Parts& p = *parts_;
  if (tracks_.empty()) {
    p.text->SetInput(notes_.front().c_str());
    return;
  }
  const PoseTrack::Pose pose = tracks_.front().at(t);
  const double z = p.geometry.wheel_radius;
  const double speed = speed_at(t);
  place(p.rover, pose, z, speed);
  position_ = Eigen::Vector3d(pose.east, pose.north, z);
  if (p.has_ghost) place(p.ghost, tracks_[1].at(t), z, speed);
  show_slip(t);
  show_text(t, speed, pose.yaw);
  chase(pose.east, pose.north, pose.yaw);
}

// Speed from the pose track's displacement over half a second.
double RoverScene::speed_at(double t) const {
  const auto& tr = tracks_.front();
  const PoseTrack::Pose ahead = tr.at(t + 0.25), behind = tr.at(t - 0.25);
  const double span = std::min(t + 0.25, tr.time.back()) - std::max(t - 0.25, tr.time.front());
  return span > 0 ? std::hypot(ahead.east - behind.east, ahead.north - behind.north) / span : 0.0;
}

// The estimated slip class on the wheels (grey when undefined).
void RoverScene::show_slip(double t) {
  Parts& p = *parts_;
  shown_class_ = -1;
  shown_slip_ = NAN;
  if (p.slip != nullptr && t >= p.slip->start_time() - 0.2 && t <= p.slip->end_time() + 0.2) {
    const std::size_t k = p.slip->nearest_index(t);
    const double c = p.slip->channel("slip_class").values[k];
    shown_slip_ = p.slip->channel("slip_ratio").values[k];
    shown_class_ = std::isfinite(c) ? static_cast<int>(c) : -1;
  }
  const Eigen::Vector3d wc = slip_class_colour(shown_class_);
  for (auto& w : p.rover.wheels) w->GetProperty()->SetColor(wc.x(), wc.y(), wc.z());
}

void RoverScene::show_text(double t, double speed, double yaw) {
  Parts& p = *parts_;
  char line[256];
  std::snprintf(line, sizeof line, "t = %.2f s   speed %.2f m/s   heading %.0f deg   pose: %s", t, speed,
                std::fmod(yaw * 180.0 / M_PI + 720.0, 360.0), pose_source_.c_str());
  std::string text = line;
  if (shown_class_ >= 0) {
    std::snprintf(line, sizeof line, "\nslip %.2f (%s)", shown_slip_,
                  estimation::to_string(static_cast<estimation::SlipClass>(shown_class_)));
    text += line;
  } else if (p.slip != nullptr) {
    text += "\nslip undefined (too slow)";
  }
  if (p.truth_slip != nullptr) {
    const double s = p.truth_slip->channel("slip_ratio").values[p.truth_slip->nearest_index(t)];
    std::snprintf(line, sizeof line, "   truth %.2f (%s)", s, estimation::to_string(estimation::classify_slip(s)));
    text += line;
  }
  p.text->SetInput(text.c_str());
}

// Chase camera: behind and above, looking at the rover.
void RoverScene::chase(double east, double north, double yaw) {
  const double z = parts_->geometry.wheel_radius;
  vtkCamera* cam = parts_->renderer->GetActiveCamera();
  const double back = 3.6, height = 1.6;
  cam->SetFocalPoint(east, north, z);
  cam->SetPosition(east - back * std::sin(yaw), north - back * std::cos(yaw), z + height);
  cam->SetViewUp(0, 0, 1);
  cam->SetViewAngle(40.0);
  parts_->renderer->ResetCameraClippingRange();
}

namespace {

// A DH rover whose joint angles the log holds is drawn articulated.
bool articulated(const SceneInput& in) {
  return in.articulated && articulated_rover_needs(*in.log, &*in.articulated).empty();
}

// `rover`: the planar rover in 3D for a planar rocker-bogie log, the
// articulated 3D rover for a DH rover's log, else the 3D skid-steer rover.
class RoverView : public View {
 public:
  std::string name() const override { return "rover"; }
  std::string title() const override { return "Rover"; }
  std::string needs(const SceneInput& in) const override {
    if (is_planar_rocker_bogie_log(*in.log)) return planar_rover_needs(*in.log);
    return articulated(in) ? std::string() : pose_track_needs(*in.log);
  }
  bool trackball_camera() const override { return true; }
  // Pose and slip (skid-steer), contact angles (articulated), net traction (planar).
  std::vector<std::string> estimates_drawn() const override {
    return {estimation::ins_streams::kPrefix, estimation::ins_streams::kOdometryPrefix,
            estimation::contact_streams::kPrefix, estimation::net_traction_streams::kPrefix};
  }

 protected:
  std::unique_ptr<Scene> make_scene(const SceneInput& in) const override {
    if (is_planar_rocker_bogie_log(*in.log)) return std::make_unique<PlanarRoverScene>(*in.log);
    if (articulated(in)) return std::make_unique<ArticulatedRoverScene>(*in.log, *in.articulated);
    return std::make_unique<RoverScene>(*in.log, in.rover);
  }
};

}  // namespace

std::unique_ptr<View> make_rover_view() { return std::make_unique<RoverView>(); }

}  // namespace roverlab::views
