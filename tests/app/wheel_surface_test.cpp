// Issue 44 item 4: the traction-surface view of a single-wheel file with
// several slip angles draws the points of one angle (the asked one, else the
// one nearest 0) and names it, and its slip axis holds every point drawn,
// braking (s < 0) included.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "app/view_data.h"
#include "app/views_input.h"
#include "core/common/error.h"
#include "test_support.h"

using namespace roverlab;
using namespace roverlab::test;

namespace {

// Two loads, slips -0.4 .. 0.6, slip angles 0, 10 and 30 deg; DP = load * (0.5 s - 0.01 beta_deg).
std::string steered_rows() {
  std::string rows = "wheel,radius_m,width_m,load_N,slip,slip_angle_deg,drawbar_pull_N,lateral_force_N\n";
  for (double load : {40.0, 80.0}) {
    for (double s : {-0.4, -0.1, 0.1, 0.3, 0.6}) {
      for (double beta : {30.0, 10.0, 0.0}) {
        rows += "w,0.15,0.1," + std::to_string(load) + "," + std::to_string(s) + "," + std::to_string(beta) + "," +
                std::to_string(load * (0.5 * s - 0.01 * beta)) + "," + std::to_string(beta == 0 ? 0.0 : -5.0) + "\n";
      }
    }
  }
  return rows;
}

}  // namespace

TEST(WheelSurface, DrawsThePointsOfOneSlipAngleNamedAndEveryOneInsideTheSlipAxis) {
  TempDir dir;
  const std::string csv = dir.file("steer.csv");
  write_text(csv, steered_rows());
  const app::ViewInput in = app::load_view_input(csv, std::nullopt, {});
  ASSERT_EQ(in.wheel_points.size(), 30u);
  // Default: the angle nearest 0, 10 of the 30 points.
  const views::TractionSurfaceData d = app::traction_surface_of(in, "drawbar-pull", std::nullopt);
  ASSERT_EQ(d.points.size(), 10u);
  for (const auto& p : d.points) EXPECT_NEAR(p.value, p.load * 0.5 * p.slip, 1e-3);  // only beta = 0 rows
  EXPECT_NE(d.quantity.find("slip angle 0 deg"), std::string::npos) << d.quantity;
  for (const auto& p : d.points) {
    EXPECT_GE(p.slip, d.slip_min);
    EXPECT_LE(p.slip, d.slip_max);
  }
  EXPECT_DOUBLE_EQ(d.slip_min, -0.4);  // braking points inside the axis
  EXPECT_DOUBLE_EQ(d.slip_max, 1.0);
  // Asked: 30 deg, its own 10 points.
  const views::TractionSurfaceData d30 = app::traction_surface_of(in, "drawbar-pull", std::nullopt, nullptr, 30.0);
  ASSERT_EQ(d30.points.size(), 10u);
  for (const auto& p : d30.points) EXPECT_NEAR(p.value, p.load * (0.5 * p.slip - 0.3), 1e-3);
  EXPECT_NE(d30.quantity.find("slip angle 30 deg"), std::string::npos) << d30.quantity;
  // With a soil: the model at that angle, the same points.
  const views::TractionSurfaceData model =
      app::traction_surface_of(in, "drawbar-pull", std::string("dry_sand"), nullptr, 10.0);
  EXPECT_EQ(model.points.size(), 10u);
  EXPECT_NE(model.quantity.find("dry_sand model, slip angle 10 deg"), std::string::npos) << model.quantity;
  EXPECT_DOUBLE_EQ(model.slip_min, -0.4);
  // An angle the file lacks: one line naming the file and the angles it has.
  try {
    app::traction_surface_of(in, "drawbar-pull", std::nullopt, nullptr, 15.0);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("steer.csv"), std::string::npos) << what;
    EXPECT_NE(what.find("slip angles 0, 10, 30 deg"), std::string::npos) << what;
  }
}
