#pragma once
// What the views need from a file named on the command line (or opened in
// the GUI): the log, with the INS estimate added when the log has IMU and
// wheels but no estimate yet; or the traction points of a single-wheel CSV.

#include <optional>
#include <string>
#include <vector>

#include "core/analysis/odometry_discrepancy.h"
#include "core/estimation/contact_angle.h"
#include "core/estimation/ins_slip.h"
#include "core/log/log.h"
#include "core/terramechanics/traction_surface.h"
#include "core/terramechanics/wheel_test.h"
#include "views/traction_surface_scene.h"

namespace roverlab::app {

struct ViewInput {
  std::string file;
  log::Log log;
  std::optional<estimation::InsSlipResult> ins;  // when the INS was run here
  std::optional<analysis::OdometryDiscrepancyReport> odometry;
  std::optional<estimation::ContactAngleResult> contact;
  std::vector<terramechanics::WheelTestPoint> wheel_points;  // single-wheel CSV input
  std::vector<std::string> notes;  // what was computed or is missing, one line each
  bool is_wheel_test() const { return !wheel_points.empty(); }
};

struct ViewInputOptions {
  bool run_estimator = true;   // INS slip when imu and wheels are present and no estimate is
  bool run_odometry_study = false;
  bool run_contact_estimator = false;  // contact angles (seed 000) when the log has joints and no estimate
};

// Loads FILE (log formats, or a single-wheel CSV with load_N and slip
// columns). Throws InputError naming the file.
ViewInput load_view_input(const std::string& file, const std::optional<std::string>& mapping,
                          const ViewInputOptions& options = {});

// The rover a log names (its rover_id); the ExoMars BB2 when it names none.
std::string rover_name_of(const log::Log& log);

// The contact-angle estimator as the views run it on a DH-rover log:
// model C+SS, EKF, cross-covariances reset (seed 000's workaround).
estimation::ContactAngleOptions view_contact_options();

// The skid-steer geometry the rover view draws: the log's rover
// description (resources/rovers/<rover_id>.json) when it is a skid-steer
// one, else the Pathfinder's defaults.
estimation::SkidSteerGeometry rover_geometry(const log::Log& log);

// A traction surface for the view, "drawbar-pull" or "torque": with a soil,
// the Wong-Reece model on a grid fitted by an order-4 polynomial (seed 003
// Appendix A) with the single-wheel points (if any) drawn against it;
// without, a polynomial fitted to the points (they must span two loads).
// Throws InputError when there is nothing to draw.
views::TractionSurfaceData traction_surface_of(const ViewInput& input, const std::string& quantity,
                                               const std::optional<std::string>& soil,
                                               terramechanics::SurfaceFit* fit = nullptr);

}  // namespace roverlab::app
