#include "views/map_scene.h"

#include <vtkActor.h>
#include <vtkActor2D.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCoordinate.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataMapper2D.h>
#include <vtkProperty.h>
#include <vtkProperty2D.h>
#include <vtkRegularPolygonSource.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/estimation/ins_slip/streams.h"
#include "core/log/stream.h"
#include "core/models/slip.h"
#include "views/rover_scene.h"
#include "views/vtk_parts.h"

namespace roverlab::views {

namespace {

// The map takes the window's left part; the legend and the north arrow sit
// in a panel at its right, never over a track.
constexpr double kPanel = 0.78;

// A planar simulation's truth: x along the path, drawn east of the start.
const log::Stream* planar_truth(const log::Log& lg) {
  const log::Stream* s = lg.find_stream("truth/pose");
  if (s == nullptr || s->size() < 2 || s->find_channel("x") == nullptr) return nullptr;
  return s;
}

std::string label_of(const std::string& source) {
  if (source == estimation::ins_streams::kPose) return "INS estimate";
  if (source == "truth/motion") return "simulated truth";
  if (source == "truth/pose") return "simulated truth (planar, x east)";
  if (source == estimation::ins_streams::kOdometryPose) return "wheel odometry";
  if (source == "gps") return "GPS";
  return source;
}

// 1, 2 or 5 times a power of ten, at most `length`.
double round_length(double length) {
  const double decade = std::pow(10.0, std::floor(std::log10(length)));
  for (double m : {5.0, 2.0, 1.0}) {
    if (m * decade <= length) return m * decade;
  }
  return decade;
}

vtkSmartPointer<vtkTextActor> world_text(double size, const Eigen::Vector3d& rgb, bool bold) {
  vtkNew<vtkTextActor> t;
  t->GetTextProperty()->SetFontSize(static_cast<int>(size));
  t->GetTextProperty()->SetColor(rgb.x(), rgb.y(), rgb.z());
  t->GetTextProperty()->SetBold(bold);
  t->GetTextProperty()->SetJustificationToCentered();
  t->GetPositionCoordinate()->SetCoordinateSystemToWorld();
  return t;
}

// A disc of radius 1 (filled) or its rim (a line), placed by the actor's scale and position.
vtkSmartPointer<vtkActor> disc(const Eigen::Vector3d& rgb, bool rim, int sides = 32) {
  vtkNew<vtkRegularPolygonSource> src;
  src->SetNumberOfSides(sides);
  src->SetRadius(1.0);
  src->SetGeneratePolygon(!rim);
  src->SetGeneratePolyline(rim);
  auto a = rim ? line_actor(src->GetOutputPort(), rgb, 2.0) : actor_of(src->GetOutputPort(), rgb);
  a->GetProperty()->SetLighting(false);
  return a;
}

// A filled rectangle in the panel's normalized viewport coordinates.
vtkSmartPointer<vtkActor2D> panel_polygon(const std::vector<std::pair<double, double>>& corners,
                                          const std::vector<std::vector<vtkIdType>>& polygons) {
  vtkNew<vtkPoints> pts;
  for (const auto& [x, y] : corners) pts->InsertNextPoint(x, y, 0);
  vtkNew<vtkCellArray> cells;
  for (const auto& ids : polygons) cells->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
  vtkNew<vtkPolyData> poly;
  poly->SetPoints(pts);
  poly->SetPolys(cells);
  vtkNew<vtkCoordinate> normalized;
  normalized->SetCoordinateSystemToNormalizedViewport();
  vtkNew<vtkPolyDataMapper2D> mapper;
  mapper->SetInputData(poly);
  mapper->SetTransformCoordinate(normalized);
  vtkNew<vtkActor2D> actor;
  actor->SetMapper(mapper);
  return actor;
}

vtkSmartPointer<vtkActor2D> panel_swatch(double x0, double y0, double x1, double y1) {
  return panel_polygon({{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, {{0, 1, 2, 3}});
}

// The north arrow, in the panel's normalized viewport coordinates.
vtkSmartPointer<vtkActor2D> north_arrow() {
  const double x = 0.5, y0 = 0.05, y1 = 0.15;
  auto arrow = panel_polygon({{x - 0.003, y0},
                              {x + 0.003, y0},
                              {x + 0.003, y1 - 0.03},
                              {x - 0.003, y1 - 0.03},
                              {x - 0.06, y1 - 0.03},
                              {x + 0.06, y1 - 0.03},
                              {x, y1}},
                             {{0, 1, 2, 3}, {4, 5, 6}});
  arrow->GetProperty()->SetColor(0.1, 0.1, 0.12);
  return arrow;
}

}  // namespace

struct MapScene::Track {
  std::string source;
  std::vector<double> time, east, north;  // finite points only
  Eigen::Vector2d at(double t) const {
    const double tc = std::clamp(t, time.front(), time.back());
    return {log::interpolate_linear(time, east, tc), log::interpolate_linear(time, north, tc)};
  }
};

struct MapScene::Parts {
  vtkSmartPointer<vtkRenderer> map, panel;
  std::vector<vtkSmartPointer<vtkActor>> lines, markers, rims;
  vtkSmartPointer<vtkActor> start, start_rim, end, grid, bar;
  vtkSmartPointer<vtkTextActor> start_text, end_text, bar_text, north_text, time_text;
  std::vector<std::string> legend_entries;
  std::vector<vtkSmartPointer<vtkTextActor>> legend_texts;
  double scale_length = 0;
  MapRect visible{};
  double marker_radius = 0.1;
  double aspect = 1.6;
};

Eigen::Vector3d MapScene::track_colour(const std::string& source) {
  if (source == estimation::ins_streams::kPose) return {0.12, 0.35, 0.85};
  if (source == "truth/motion" || source == "truth/pose") return {0.1, 0.6, 0.2};
  // Purple, not the rover view's orange: orange is a slip class here.
  if (source == estimation::ins_streams::kOdometryPose) return {0.55, 0.2, 0.75};
  return {0.15, 0.15, 0.15};  // gps
}

std::string map_needs(const log::Log& lg) {
  if (pose_track_needs(lg).empty() || planar_truth(lg) != nullptr) return {};
  return "no position to map: the log has none of estimate/ins/pose, truth/motion, estimate/odometry/pose, gps, "
         "truth/pose";
}

MapScene::MapScene(const log::Log& lg) : parts_(std::make_unique<Parts>()) {
  Parts& p = *parts_;
  p.map = vtkSmartPointer<vtkRenderer>::New();
  p.map->SetViewport(0.0, 0.0, kPanel, 1.0);
  p.map->SetBackground(0.975, 0.972, 0.955);
  p.panel = vtkSmartPointer<vtkRenderer>::New();
  p.panel->SetViewport(kPanel, 0.0, 1.0, 1.0);
  p.panel->SetBackground(1.0, 1.0, 1.0);
  read_log(lg);
  add_tracks();
  add_slip(lg);
  add_marks();
  add_legend();
  fit(1.6);
  set_time(start_);
}

MapScene::~MapScene() = default;

void MapScene::read_log(const log::Log& lg) {
  std::vector<PoseTrack> poses = pose_tracks(lg);
  if (const log::Stream* s = planar_truth(lg)) {
    PoseTrack planar;
    planar.source = s->name();
    planar.time = s->time();
    planar.east = s->channel("x").values;
    planar.north.assign(planar.time.size(), 0.0);
    poses.push_back(planar);
  }
  const double inf = std::numeric_limits<double>::infinity();
  extent_ = {inf, inf, -inf, -inf};
  for (const PoseTrack& pose : poses) {
    Track tr;
    tr.source = pose.source;
    for (std::size_t i = 0; i < pose.time.size(); ++i) {
      if (!std::isfinite(pose.time[i] + pose.east[i] + pose.north[i])) continue;
      tr.time.push_back(pose.time[i]);
      tr.east.push_back(pose.east[i]);
      tr.north.push_back(pose.north[i]);
      extent_ = {std::min(extent_[0], pose.east[i]), std::min(extent_[1], pose.north[i]),
                 std::max(extent_[2], pose.east[i]), std::max(extent_[3], pose.north[i])};
    }
    if (tr.time.size() >= 2) tracks_.push_back(std::move(tr));
  }
  if (tracks_.empty()) {
    notes_.push_back(map_needs(lg).empty() ? "no finite position in the log's pose streams" : map_needs(lg));
    extent_ = {-1, -1, 1, 1};
    return;
  }
  start_ = tracks_.front().time.front();
  end_ = tracks_.front().time.back();
}

// Every track, the best one drawn last (on top).
void MapScene::add_tracks() {
  Parts& p = *parts_;
  for (std::size_t k = 0; k < tracks_.size(); ++k) {
    const Track& tr = tracks_[k];
    std::vector<Eigen::Vector3d> points;
    const double z = 0.2 - 0.01 * static_cast<double>(k);
    for (std::size_t i = 0; i < tr.time.size(); ++i) points.emplace_back(tr.east[i], tr.north[i], z);
    const Eigen::Vector3d c = track_colour(tr.source);
    p.lines.push_back(line_actor(polyline(points), c, k == 0 ? 3.0 : 2.5));
    p.map->AddActor(p.lines.back());
    p.markers.push_back(disc(c, false));
    p.rims.push_back(disc({0.05, 0.05, 0.05}, true));
    p.map->AddActor(p.markers.back());
    p.map->AddActor(p.rims.back());
  }
}

// The slip class along the best track, as a wide band under it: the INS
// estimate's classes, else the simulated truth's slip (seed 002's classes).
void MapScene::add_slip(const log::Log& lg) {
  if (tracks_.empty()) return;
  const log::Stream* s = lg.find_stream(estimation::ins_streams::kSlip);
  const char* channel = "slip_class";
  if (s == nullptr || s->find_channel(channel) == nullptr) {
    s = lg.find_stream("truth/slip");
    channel = "slip_ratio";
    if (s == nullptr || s->find_channel(channel) == nullptr || s->size() == 0) return;
  }
  const Track& tr = tracks_.front();
  const auto& values = s->channel(channel).values;
  std::vector<Eigen::Vector3d> points;
  vtkNew<vtkUnsignedCharArray> colours;
  colours->SetNumberOfComponents(3);
  for (std::size_t i = 0; i + 1 < tr.time.size(); ++i) {
    const double t = 0.5 * (tr.time[i] + tr.time[i + 1]);
    if (t < s->start_time() - 0.2 || t > s->end_time() + 0.2) continue;
    const double v = values[s->nearest_index(t)];
    if (!std::isfinite(v)) continue;
    const int c =
        channel == std::string("slip_class") ? static_cast<int>(v) : static_cast<int>(estimation::classify_slip(v));
    if (c < 0 || c >= estimation::kSlipClasses) continue;
    points.emplace_back(tr.east[i], tr.north[i], 0.0);
    points.emplace_back(tr.east[i + 1], tr.north[i + 1], 0.0);
    const Eigen::Vector3d rgb = 255.0 * slip_class_colour(c);
    colours->InsertNextTuple3(rgb.x(), rgb.y(), rgb.z());
    ++slip_segments_[static_cast<std::size_t>(c)];
  }
  if (points.empty()) {
    notes_.emplace_back("the slip stream '" + s->name() + "' has no class along the track");
    return;
  }
  auto band = segments(points, true);
  band->GetCellData()->SetScalars(colours);
  auto actor = line_actor(band, {1, 1, 1}, 10.0);
  actor->GetMapper()->SetScalarModeToUseCellData();
  actor->GetMapper()->SetColorModeToDirectScalars();
  actor->GetMapper()->ScalarVisibilityOn();
  parts_->map->AddActor(actor);
  notes_.emplace_back("slip class along the " + label_of(tr.source) + " track from '" + s->name() + "'");
}

// Start and end of the best track, the scale bar and the grid (placed by fit),
// the north arrow and the time.
void MapScene::add_marks() {
  Parts& p = *parts_;
  p.start = disc({1, 1, 1}, false);
  p.start_rim = disc({0.05, 0.05, 0.05}, true);
  p.end = disc({0.05, 0.05, 0.05}, false, 4);
  p.start_text = world_text(15, {0.05, 0.05, 0.05}, true);
  p.start_text->SetInput("start");
  p.end_text = world_text(15, {0.05, 0.05, 0.05}, true);
  p.end_text->SetInput("end");
  p.bar_text = world_text(16, {0.05, 0.05, 0.05}, true);
  p.bar = vtkSmartPointer<vtkActor>::New();
  p.grid = vtkSmartPointer<vtkActor>::New();
  if (!tracks_.empty()) {
    for (auto* a : {p.start.Get(), p.start_rim.Get(), p.end.Get()}) p.map->AddActor(a);
    p.map->AddViewProp(p.start_text);
    p.map->AddViewProp(p.end_text);
  }
  p.panel->AddViewProp(north_arrow());
  p.north_text = vtkSmartPointer<vtkTextActor>::New();
  p.north_text->SetInput("N");
  p.north_text->GetTextProperty()->SetFontSize(20);
  p.north_text->GetTextProperty()->SetBold(true);
  p.north_text->GetTextProperty()->SetColor(0.1, 0.1, 0.12);
  p.north_text->GetTextProperty()->SetJustificationToCentered();
  p.north_text->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  p.north_text->GetPositionCoordinate()->SetValue(0.5, 0.16);
  p.panel->AddViewProp(p.north_text);
  p.time_text = vtkSmartPointer<vtkTextActor>::New();
  p.time_text->GetTextProperty()->SetFontSize(15);
  p.time_text->GetTextProperty()->SetColor(0.05, 0.05, 0.1);
  p.time_text->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  p.time_text->GetPositionCoordinate()->SetValue(0.06, 0.22);
  p.panel->AddViewProp(p.time_text);
}

// The tracks, then the slip classes drawn, each a colour swatch and its name
// in the panel beside the map (a legend that never covers a track).
void MapScene::add_legend() {
  Parts& p = *parts_;
  std::vector<std::pair<std::string, Eigen::Vector3d>> entries;
  for (const Track& tr : tracks_) entries.emplace_back(label_of(tr.source), track_colour(tr.source));
  for (int c = 0; c < estimation::kSlipClasses; ++c) {
    if (slip_segments_[static_cast<std::size_t>(c)] == 0) continue;
    entries.emplace_back(std::string("slip ") + estimation::to_string(static_cast<estimation::SlipClass>(c)),
                         slip_class_colour(c));
  }
  double y = 0.95;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (i == tracks_.size()) y -= 0.03;  // the slip classes apart from the tracks
    const Eigen::Vector3d& c = entries[i].second;
    auto box = panel_swatch(0.06, y - 0.005, 0.085, y + 0.02);
    box->GetProperty()->SetColor(c.x(), c.y(), c.z());
    p.panel->AddViewProp(box);
    vtkNew<vtkTextActor> text;
    text->SetInput(entries[i].first.c_str());
    text->GetTextProperty()->SetFontSize(17);  // fit() sizes it to the panel
    text->GetTextProperty()->SetColor(0.05, 0.05, 0.1);
    text->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    text->GetPositionCoordinate()->SetValue(0.14, y - 0.005);
    p.panel->AddViewProp(text);
    p.legend_texts.emplace_back(text);
    p.legend_entries.push_back(entries[i].first);
    y -= 0.045;
  }
}

// A parallel camera showing every track whole with a margin and room below
// for the scale bar; the grid, the scale bar and the marks sized to it.
void MapScene::fit(double aspect) {
  Parts& p = *parts_;
  p.aspect = aspect;
  const double cx = 0.5 * (extent_[0] + extent_[2]), cy = 0.5 * (extent_[1] + extent_[3]);
  const double size = std::max({extent_[2] - extent_[0], extent_[3] - extent_[1], 1.0});
  const double margin = 0.06 * size, room = 0.1 * size;
  const double w = std::max(extent_[2] - extent_[0], 1.0) + 2 * margin;
  const double h = std::max(extent_[3] - extent_[1], 1.0) + 2 * margin + room;
  const double half_height = std::max(0.5 * h, 0.5 * w / aspect);
  const double centre_north = cy - 0.5 * room;
  vtkCamera* cam = p.map->GetActiveCamera();
  cam->ParallelProjectionOn();
  cam->SetFocalPoint(cx, centre_north, 0.0);
  cam->SetPosition(cx, centre_north, 10.0 * size);
  cam->SetViewUp(0, 1, 0);
  cam->SetParallelScale(half_height);
  p.map->ResetCameraClippingRange(cx - size, cx + size, cy - size, cy + size, -1.0, 1.0);
  p.visible = {cx - half_height * aspect, centre_north - half_height, cx + half_height * aspect,
               centre_north + half_height};
  const double vw = p.visible[2] - p.visible[0], vh = p.visible[3] - p.visible[1];
  const double pixel = vh / 800.0;  // about one pixel of an 800-pixel-high window
  // The scale bar: a round length near a fifth of the width, under the tracks.
  p.scale_length = round_length(0.2 * vw);
  const double x0 = p.visible[0] + 0.05 * vw, y = std::min(extent_[1] - margin - 0.55 * room, p.visible[1] + 0.05 * vh);
  const double tick = 0.012 * vh;
  const double x1 = x0 + p.scale_length;
  p.bar->SetMapper(line_actor(segments({{x0, y, 0.5},
                                        {x1, y, 0.5},
                                        {x0, y - tick, 0.5},
                                        {x0, y + tick, 0.5},
                                        {x1, y - tick, 0.5},
                                        {x1, y + tick, 0.5}},
                                       true),
                              {0.05, 0.05, 0.05}, 3.0)
                       ->GetMapper());
  p.bar->GetProperty()->SetLineWidth(3.0);
  p.bar->GetProperty()->SetLighting(false);
  p.bar->GetProperty()->SetColor(0.05, 0.05, 0.05);
  p.bar_text->SetInput(scale_text().c_str());
  p.bar_text->GetPositionCoordinate()->SetValue(0.5 * (x0 + x1), y + tick + 4 * pixel, 0.5);
  if (p.map->GetActors()->IsItemPresent(p.bar) == 0) {
    p.map->AddActor(p.bar);
    p.map->AddViewProp(p.bar_text);
    p.map->AddActor(p.grid);
  }
  // A faint grid at the scale bar's spacing.
  std::vector<Eigen::Vector3d> grid;
  const double step = p.scale_length;
  for (double e = std::ceil(p.visible[0] / step) * step; e <= p.visible[2]; e += step) {
    grid.emplace_back(e, p.visible[1], -0.5);
    grid.emplace_back(e, p.visible[3], -0.5);
  }
  for (double n = std::ceil(p.visible[1] / step) * step; n <= p.visible[3]; n += step) {
    grid.emplace_back(p.visible[0], n, -0.5);
    grid.emplace_back(p.visible[2], n, -0.5);
  }
  p.grid->SetMapper(line_actor(segments(grid, true), {0.86, 0.86, 0.83}, 1.0)->GetMapper());
  p.grid->GetProperty()->SetLighting(false);
  p.grid->GetProperty()->SetColor(0.86, 0.86, 0.83);
  // Marks a fixed number of pixels across.
  p.marker_radius = 7 * pixel;
  if (tracks_.empty()) return;
  const Track& best = tracks_.front();
  const double r = p.marker_radius;
  p.start->SetPosition(best.east.front(), best.north.front(), 0.6);
  p.start_rim->SetPosition(best.east.front(), best.north.front(), 0.61);
  p.end->SetPosition(best.east.back(), best.north.back(), 0.6);
  for (auto* a : {p.start.Get(), p.start_rim.Get(), p.end.Get()}) a->SetScale(r, r, 1);
  p.start_text->GetPositionCoordinate()->SetValue(best.east.front() + 3 * r, best.north.front() - 3.5 * r, 0.7);
  p.end_text->GetPositionCoordinate()->SetValue(best.east.back() + 3 * r, best.north.back() + 1.5 * r, 0.7);
  for (std::size_t k = 0; k < tracks_.size(); ++k) {
    p.markers[k]->SetScale(r, r, 1);
    p.rims[k]->SetScale(r, r, 1);
  }
}

vtkRenderer* MapScene::renderer() const { return parts_->map; }

void MapScene::attach(vtkRenderWindow* window) {
  window->AddRenderer(parts_->map);
  window->AddRenderer(parts_->panel);
  const int* size = window->GetSize();
  if (size[0] > 0 && size[1] > 0) fit(kPanel * size[0] / size[1]);
}

void MapScene::detach(vtkRenderWindow* window) {
  window->RemoveRenderer(parts_->map);
  window->RemoveRenderer(parts_->panel);
}

void MapScene::fit_width(int pixels) {
  // The window's own shape (a GUI pane may be narrower than the width asked for).
  vtkRenderWindow* window = parts_->map->GetRenderWindow();
  const int* size = window != nullptr ? window->GetSize() : nullptr;
  if (size != nullptr && size[0] > 0 && size[1] > 0) {
    pixels = size[0];
    fit(kPanel * size[0] / size[1]);
  }
  // The legend's names fit the panel: about 11 characters' width of it.
  const int font = std::clamp(static_cast<int>((1.0 - kPanel) * pixels / 11.0), 10, 17);
  for (auto& text : parts_->legend_texts) text->GetTextProperty()->SetFontSize(font);
}

void MapScene::set_time(double t) {
  Parts& p = *parts_;
  for (std::size_t k = 0; k < tracks_.size(); ++k) {
    const Eigen::Vector2d at = tracks_[k].at(t);
    const double z = 0.8 + 0.01 * static_cast<double>(tracks_.size() - k);
    p.markers[k]->SetPosition(at.x(), at.y(), z);
    p.rims[k]->SetPosition(at.x(), at.y(), z + 0.005);
  }
  char line[64];
  std::snprintf(line, sizeof line, "t = %.2f s", t);
  p.time_text->SetInput(tracks_.empty() ? notes_.front().c_str() : line);
}

std::vector<std::string> MapScene::sources() const {
  std::vector<std::string> out;
  for (const Track& tr : tracks_) out.push_back(tr.source);
  return out;
}

MapRect MapScene::track_bounds(std::size_t k) const {
  const double* b = parts_->lines.at(k)->GetBounds();
  return {b[0], b[2], b[1], b[3]};
}

MapRect MapScene::visible() const {
  vtkCamera* cam = parts_->map->GetActiveCamera();
  const double* f = cam->GetFocalPoint();
  const double half_height = cam->GetParallelScale();
  // The aspect of the map's viewport in the window it is in, else the one last fitted.
  double aspect = parts_->aspect;
  if (vtkRenderWindow* window = parts_->map->GetRenderWindow(); window != nullptr && window->GetSize()[1] > 0) {
    aspect = kPanel * window->GetSize()[0] / window->GetSize()[1];
  }
  const double half_width = half_height * aspect;
  return {f[0] - half_width, f[1] - half_height, f[0] + half_width, f[1] + half_height};
}

double MapScene::scale_length() const { return parts_->scale_length; }

std::string MapScene::scale_text() const {
  char text[32];
  std::snprintf(text, sizeof text, "%g m", parts_->scale_length);
  return text;
}

std::vector<std::string> MapScene::legend_entries() const { return parts_->legend_entries; }

Eigen::Vector2d MapScene::marker(std::size_t k) const {
  const double* at = parts_->markers.at(k)->GetPosition();
  return {at[0], at[1]};
}

namespace {

class MapView : public View {
 public:
  std::string name() const override { return "map"; }
  std::string title() const override { return "Map"; }
  std::string heading() const override { return "Map: where the rover went, every pose source, north up"; }
  std::string needs(const SceneInput& in) const override { return map_needs(*in.log); }
  std::vector<std::string> estimates_drawn() const override {
    return {estimation::ins_streams::kPrefix, estimation::ins_streams::kOdometryPrefix};
  }

 protected:
  std::unique_ptr<Scene> make_scene(const SceneInput& in) const override { return std::make_unique<MapScene>(*in.log); }
};

}  // namespace

std::unique_ptr<View> make_map_view() { return std::make_unique<MapView>(); }

}  // namespace roverlab::views
