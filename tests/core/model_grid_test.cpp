#include <gtest/gtest.h>

#include <cmath>

#include "core/terramechanics/model_grid.h"
#include "core/terramechanics/rft.h"
#include "terramechanics_soils.h"

using namespace roverlab::terramechanics;

namespace {

GridModel kapvik_on(const Soil& soil, ModelKind kind = ModelKind::wong_reece) {
  GridModel m;
  m.soil = soil;
  m.wheel = roverlab::test::kapvik_wheel();
  m.options.kind = kind;
  return m;
}

}  // namespace

TEST(ModelGrid, NodesSpanTheRangesAndEachValueIsTheModelsAtItsNode) {
  const GridModel model = kapvik_on(roverlab::test::dry_sand());
  const GridRange range{10.0, 120.0, -0.5, 0.9, 7, 9};
  const ModelGrid g = model_grid(model, range, std::nullopt);
  EXPECT_EQ(g.drawbar_pull.size() + g.unsupported, 63u);
  ASSERT_EQ(g.drawbar_pull.size(), g.resistive_torque.size());
  ASSERT_FALSE(g.drawbar_pull.empty());
  EXPECT_DOUBLE_EQ(g.drawbar_pull.front().load, 10.0);
  EXPECT_DOUBLE_EQ(g.drawbar_pull.front().slip, -0.5);
  for (std::size_t i = 0; i < g.drawbar_pull.size(); ++i) {
    const SurfaceSample& s = g.drawbar_pull[i];
    const Traction t = evaluate(model.soil, model.wheel, s.load, s.slip, model.options);
    ASSERT_TRUE(t.ok());
    EXPECT_EQ(s.value, t.drawbar_pull);
    EXPECT_EQ(g.resistive_torque[i].value, t.resistive_torque);
    EXPECT_EQ(g.lateral_force[i].value, 0.0);  // no slip angle: no lateral force
  }
  // Drawbar pull rises with slip at a fixed load (Wong-Reece on sand).
  EXPECT_LT(g.drawbar_pull[0].value, g.drawbar_pull[8].value);
}

TEST(ModelGrid, AtASlipAngleEvaluatesTheSlipAngleModelAndRftWhenAsked) {
  const double beta = 30.0 * M_PI / 180.0;
  for (ModelKind kind : {ModelKind::ishigami, ModelKind::rft}) {
    const GridModel model = kapvik_on(roverlab::test::dry_sand(), kind);
    const ModelCurve c = model_curve(model, 40.0, beta, -0.4, 0.8, 5);
    ASSERT_EQ(c.slip.size(), 5u);
    EXPECT_DOUBLE_EQ(c.slip.front(), -0.4);
    EXPECT_DOUBLE_EQ(c.slip.back(), 0.8);
    for (std::size_t k = 0; k < c.slip.size(); ++k) {
      const SlipAngleTraction t =
          kind == ModelKind::rft ? evaluate_rft(model.soil, model.wheel, 40.0, c.slip[k], beta, model.options)
                                 : evaluate_slip_angle(model.soil, model.wheel, 40.0, c.slip[k], beta, model.options);
      ASSERT_EQ(c.traction[k].ok(), t.ok());
      EXPECT_EQ(c.traction[k].lateral_force, t.lateral_force);
      EXPECT_EQ(c.traction[k].drawbar_pull, t.drawbar_pull);
    }
    // A wheel at a positive slip angle is pushed towards -y.
    EXPECT_LT(c.traction.back().lateral_force, 0.0);
  }
}

TEST(ModelGrid, CountsTheNodesTheSoilCannotCarry) {
  const GridModel model = kapvik_on(roverlab::test::dry_sand());
  const ModelGrid g = model_grid(model, GridRange{10.0, 1e5, 0.0, 1.0, 4, 4}, std::nullopt);
  EXPECT_GT(g.unsupported, 0u);
  EXPECT_EQ(g.drawbar_pull.size() + g.unsupported, 16u);
  int rows = 0;
  model_grid(model, GridRange{10.0, 50.0, 0.0, 1.0, 3, 2}, std::nullopt, [&](int i, int n) {
    EXPECT_EQ(i, rows++);
    EXPECT_EQ(n, 3);
  });
  EXPECT_EQ(rows, 3);
  EXPECT_THROW(model_grid(model, GridRange{10.0, 50.0, 0.0, 1.0, 1, 2}, std::nullopt), std::invalid_argument);
}
