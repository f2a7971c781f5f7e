#pragma once
// What the registry's views (views/view.h) are built from, for a file the
// app opened: the rover geometry its description gives, the channels asked
// for, the traction surface computed from single-wheel points or a soil —
// what views/ cannot know (resources, soils, the command line).

#include <optional>
#include <string>
#include <vector>

#include "app/views_input.h"
#include "core/models/skid_steer_odometry.h"
#include "core/terramechanics/traction_surface.h"
#include "views/view.h"

namespace roverlab::app {

// The skid-steer geometry the rover view draws: the log's rover
// description (resources/rovers/<rover_id>.json) when it is a skid-steer
// one, else the Pathfinder's defaults.
estimation::SkidSteerGeometry rover_geometry(const log::Log& log);
// The log's rover as a DH chain (resources/rovers/<rover_id>.json), when it has one.
std::optional<kinematics::RoverModel> rover_kinematics(const log::Log& log);

// A traction surface for the view, "drawbar-pull" or "torque": with a soil,
// the Wong-Reece model on a grid fitted by an order-4 polynomial (seed 003
// Appendix A) with the single-wheel points (if any) drawn against it;
// without, a polynomial fitted to the points (they must span two loads).
// Throws InputError when there is nothing to draw.
// "lateral-force": F_y(W, s) at one slip angle (issue 33), the surface
// fitted as the drawbar pull's, through the points at that angle, or the
// soil's Ishigami 2007 model; the angle is `slip_angle_deg`, else the
// largest the points have, else 10 deg. Points are grouped by wheel.
views::TractionSurfaceData traction_surface_of(const ViewInput& input, const std::string& quantity,
                                               const std::optional<std::string>& soil,
                                               terramechanics::SurfaceFit* fit = nullptr,
                                               std::optional<double> slip_angle_deg = std::nullopt);

// What the command line or the GUI asks of a view.
struct ViewOptions {
  std::optional<std::string> channel_spec;  // "stream:channel,..." (parse_channels), for views that plot channels
  std::vector<views::ChannelRef> channels;  // or the channels themselves; neither: the view's default
  std::optional<std::string> soil;          // the model surface's soil, for views of a traction surface
  std::string quantity = "drawbar-pull";
  std::optional<double> slip_angle_deg;  // the lateral-force surface's slip angle
  std::optional<double> time;
  std::optional<std::string> x_channel, y_channel;  // "stream:channel" each, for a view that plots_channel_pair()
  std::vector<std::pair<std::string, const log::Log*>>
      compared;  // other runs (name, log), for a view that compares_runs()
};

// The input `view` is built from on `in`. Throws InputError naming the file
// when the view cannot be drawn from it: a log view of single-wheel points,
// an unknown channel, no traction data, or what the view's needs() says.
views::SceneInput scene_input(const ViewInput& in, const views::View& view, const ViewOptions& options);

}  // namespace roverlab::app
