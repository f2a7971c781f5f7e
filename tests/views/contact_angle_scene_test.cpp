// The contact-angle scene on a small estimate made here: six wheels, FL's
// velocity 30 deg up and RR's 30 deg down, the others level; one panel per
// wheel, each arrow pointing where its wheel moves.
#include <gtest/gtest.h>

#include <cmath>

#include "core/common/error.h"
#include "core/log/log.h"
#include "scene_support.h"
#include "views/contact_angle_scene.h"

using namespace roverlab;
using namespace roverlab::test;

namespace {

const char* const kWheels[] = {"FL", "ML", "RL", "RR", "MR", "FR"};

log::Log contact_estimate() {
  log::Log lg;
  const std::vector<double> t = times(4.0, 0.01);
  log::Stream s("estimate/contact/wheels", t);
  for (const char* w : kWheels) {
    const double angle = std::string(w) == "FL" ? 0.5236 : std::string(w) == "RR" ? -0.5236 : 0.0;
    s.add_channel(std::string("contact_angle_") + w, "rad", std::vector<double>(t.size(), angle));
    s.add_channel(std::string("side_slip_") + w, "rad", std::vector<double>(t.size(), 0.0));
  }
  lg.add_stream(std::move(s));
  return lg;
}

}  // namespace

TEST(ContactAngleScene, OnePanelPerWheelWithTheArrowAlongItsVelocity) {
  const log::Log lg = contact_estimate();
  views::ContactAngleScene scene(lg);
  ASSERT_EQ(scene.wheels().size(), 6u);
  EXPECT_EQ(scene.renderers().size(), 6u);
  // Panels 200 x 200: FL ML RL on the top row, FR MR RR below.
  const views::Image img = render_scene(scene, 600, 400, 2.0);
  EXPECT_NEAR(scene.shown_contact_angle(0), 0.5236, 1e-12);
  EXPECT_NEAR(scene.shown_contact_angle(1), 0.0, 1e-12);
  auto side_view = [&](int x0, int y0) { return find_pixels(img, estimate_blue, x0, x0 + 120, y0, y0 + 180); };
  const Region fl = side_view(0, 0), ml = side_view(200, 0), rr = side_view(400, 200), mr = side_view(200, 200);
  for (const Region* r : {&fl, &ml, &rr, &mr}) EXPECT_GT(r->count, 40);
  EXPECT_LT(fl.mean_y - ml.mean_y, -4.0);  // FL's arrow points up
  EXPECT_GT(rr.mean_y - mr.mean_y, 4.0);   // RR's down
}

TEST(ContactAngleScene, NeedsTheContactAngleEstimate) {
  const log::Log empty;
  EXPECT_NE(views::contact_angle_needs(empty).find("estimate/contact/wheels"), std::string::npos);
  EXPECT_THROW(views::ContactAngleScene{empty}, DataError);
  EXPECT_EQ(views::contact_angle_needs(contact_estimate()), "");
}
