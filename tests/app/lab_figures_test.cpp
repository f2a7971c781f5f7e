// Issue 44: the per-slip-angle panels and the residuals-against-slip-angle
// view of a single-wheel file read back through their data: one panel per
// slip angle with that angle's points, the model's curve as the model gives
// it, a band of +-2 sigma of the held-out residuals, every point inside the
// axes; and the study's final model, when given, drawn instead of the baseline.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

#include "app/lab_figures.h"
#include "app/view_data.h"
#include "app/views_input.h"
#include "core/common/error.h"
#include "importers/soil_file.h"
#include "test_support.h"

using namespace roverlab;
using namespace roverlab::test;
using terramechanics::Quantity;

namespace {

constexpr double kOffset = 1.0;  // N added to the model's drawbar pull in the file

terramechanics::Soil dry_sand() { return io::find_soil("dry_sand", {std::string(ROVERLAB_RESOURCES_DIR) + "/soils"}); }

terramechanics::GridModel truth(terramechanics::SlipDefinition reading) {
  terramechanics::GridModel m;
  m.soil = dry_sand();
  m.wheel = {0.0625, 0.06, 0, 0.0};
  m.options.kind = terramechanics::ModelKind::ishigami;
  m.options.slip_definition = reading;
  return m;
}

// Ishigami on dry_sand (travel slip) at 20 N, slip angles 60, 0 and 30 deg:
// drawbar pull + kOffset, lateral force as the model gives it.
std::string model_rows() {
  const terramechanics::GridModel m = truth(terramechanics::SlipDefinition::travel);
  std::string rows = "wheel,radius_m,width_m,load_N,slip,slip_angle_deg,drawbar_pull_N,lateral_force_N\n";
  for (double beta : {60.0, 0.0, 30.0}) {
    for (double s : {-0.3, 0.0, 0.2, 0.4, 0.6}) {
      const auto t = terramechanics::model_at(m, 20.0, s, beta * M_PI / 180.0);
      char row[200];
      std::snprintf(row, sizeof row, "smooth,0.0625,0.06,20,%g,%g,%.12g,%.12g\n", s, beta, t.drawbar_pull + kOffset,
                    t.lateral_force);
      rows += row;
    }
  }
  return rows;
}

}  // namespace

TEST(LabFigures, SlipPanelsHoldEachAnglesPointsTheModelsCurveAndTwoSigmaOfItsResiduals) {
  TempDir dir;
  const std::string csv = dir.file("angles.csv");
  write_text(csv, model_rows());
  const app::ViewInput in = app::load_view_input(csv, std::nullopt, {});
  ASSERT_EQ(in.wheel_points.size(), 15u);
  const views::LabFigures f = app::lab_figures_of(in, std::nullopt);
  ASSERT_TRUE(f.slip_panels && f.residuals) << f.why_not;
  const views::PanelFigure& p = *f.slip_panels;
  // The reading the points were made with is the one chosen, and said.
  EXPECT_NE(p.caption.find("travel slip"), std::string::npos) << p.caption;
  EXPECT_EQ(p.x_title, "slip");
  ASSERT_EQ(p.rows.size(), 2u);
  EXPECT_EQ(p.rows[0].y_title, "drawbar pull (N)");
  EXPECT_EQ(p.rows[1].y_title, "lateral force (N)");
  ASSERT_EQ(p.group_names, std::vector<std::string>{"smooth, 20 N"});
  const terramechanics::GridModel model = truth(terramechanics::SlipDefinition::travel);
  const double angles[] = {0.0, 30.0, 60.0};  // sorted, whatever the file's order
  for (std::size_t row = 0; row < 2; ++row) {
    ASSERT_EQ(p.rows[row].panels.size(), 3u);
    for (std::size_t k = 0; k < 3; ++k) {
      const views::Panel& panel = p.rows[row].panels[k];
      EXPECT_EQ(panel.title, "slip angle " + std::to_string(static_cast<int>(angles[k])) + " deg");
      ASSERT_EQ(panel.series.size(), 1u);
      const views::PanelSeries& s = panel.series[0];
      ASSERT_EQ(s.x.size(), 5u);  // that angle's five rows, and only they
      const double beta = angles[k] * M_PI / 180.0;
      for (std::size_t i = 0; i < s.x.size(); ++i) {
        const auto t = terramechanics::model_at(model, 20.0, s.x[i], beta);
        EXPECT_NEAR(s.y[i], row == 0 ? t.drawbar_pull + kOffset : t.lateral_force, 1e-9);
      }
      // The curve is the model over the file's slips; the drawbar pull's band is 2 x RMS(+kOffset).
      EXPECT_DOUBLE_EQ(s.curve_x.front(), -0.3);
      EXPECT_DOUBLE_EQ(s.curve_x.back(), 0.6);
      const auto end = terramechanics::model_at(model, 20.0, 0.6, beta);
      EXPECT_NEAR(s.curve_y.back(), row == 0 ? end.drawbar_pull : end.lateral_force, 1e-12);
      EXPECT_NEAR(s.band, row == 0 ? 2.0 * kOffset : 0.0, 1e-6);
    }
  }
  // Every point, curve value and band edge inside the axes.
  const views::PanelRanges r = views::panel_ranges(p);
  for (std::size_t row = 0; row < 2; ++row) {
    for (const auto& panel : p.rows[row].panels) {
      for (const auto& s : panel.series) {
        for (std::size_t i = 0; i < s.x.size(); ++i) {
          EXPECT_GT(s.x[i], r.x_min);
          EXPECT_LT(s.x[i], r.x_max);
          EXPECT_GT(s.y[i], r.y_min[row]);
          EXPECT_LT(s.y[i], r.y_max[row]);
        }
        for (double y : s.curve_y) {
          if (!std::isfinite(y)) continue;
          EXPECT_GE(y - s.band, r.y_min[row]);
          EXPECT_LE(y + s.band, r.y_max[row]);
        }
      }
    }
  }
}

// A wheel tested at many loads (a file of jittered loads): its points in 4
// load bins of about equal size, each drawn at its bin's median load, named
// by its range and ordered by load, and the figure says so; a wheel tested
// at two loads keeps a group per load. At one slip angle the residuals are
// drawn against slip.
TEST(LabFigures, AWheelTestedAtManyLoadsHasItsLoadsBinned) {
  const terramechanics::GridModel m = truth(terramechanics::SlipDefinition::travel);
  std::string rows = "wheel,radius_m,width_m,load_N,slip,drawbar_pull_N\n";
  std::vector<double> loads;
  for (int i = 0; i < 80; ++i) {
    // Spread over 15-25 N in no order, to 0.1 mN as written.
    const double load = std::round((15.0 + 10.0 * std::fmod(0.618034 * i, 1.0)) * 1e4) / 1e4;
    const double s = -0.2 + 0.1 * (i % 8);
    char row[160];
    std::snprintf(row, sizeof row, "jittered,0.0625,0.06,%.4f,%g,%.12g\n", load, s,
                  terramechanics::model_at(m, load, s, std::nullopt).drawbar_pull);
    rows += row;
    loads.push_back(load);
  }
  for (double load : {20.0, 30.0}) {
    for (double s : {0.0, 0.3}) {
      char row[160];
      std::snprintf(row, sizeof row, "two_loads,0.0625,0.06,%g,%g,%.12g\n", load, s,
                    terramechanics::model_at(m, load, s, std::nullopt).drawbar_pull);
      rows += row;
    }
  }
  TempDir dir;
  const std::string csv = dir.file("loads.csv");
  write_text(csv, rows);
  const app::ViewInput in = app::load_view_input(csv, std::nullopt, {});
  ASSERT_EQ(in.wheel_points.size(), 84u);
  const views::LabFigures f = app::lab_figures_of(in, std::nullopt);
  ASSERT_TRUE(f.slip_panels) << f.why_not;
  const views::PanelFigure& p = *f.slip_panels;
  ASSERT_EQ(p.group_names.size(), 6u);
  EXPECT_EQ(p.group_names[4], "two_loads, 20 N");
  EXPECT_EQ(p.group_names[5], "two_loads, 30 N");
  ASSERT_EQ(p.notes.size(), 1u);
  EXPECT_NE(p.notes[0].find("loads binned"), std::string::npos) << p.notes[0];
  ASSERT_EQ(p.rows.size(), 1u);
  ASSERT_EQ(p.rows[0].panels.size(), 1u);
  const auto& series = p.rows[0].panels[0].series;
  ASSERT_EQ(series.size(), 6u);
  std::size_t drawn = 0;
  double last_median = 0.0;
  for (int g = 0; g < 4; ++g) {
    const views::PanelSeries& s = series[static_cast<std::size_t>(g)];
    EXPECT_EQ(s.group, g);
    EXPECT_EQ(p.group_names[static_cast<std::size_t>(g)].rfind("jittered, ", 0), 0u) << p.group_names[g];
    EXPECT_GE(s.x.size(), 18u);  // 80 points in 4 bins of about 20
    EXPECT_LE(s.x.size(), 22u);
    drawn += s.x.size();
    // Which loads are in the bin: those whose drawbar pull at their slip the points show.
    std::vector<double> in_bin;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      for (double load : loads) {
        if (std::abs(terramechanics::model_at(m, load, s.x[i], std::nullopt).drawbar_pull - s.y[i]) < 1e-9) {
          in_bin.push_back(load);
          break;
        }
      }
    }
    ASSERT_EQ(in_bin.size(), s.x.size());
    std::sort(in_bin.begin(), in_bin.end());
    const double median = in_bin[in_bin.size() / 2];
    EXPECT_GT(median, last_median);  // ordered by load
    last_median = median;
    const auto end = terramechanics::model_at(m, median, s.curve_x.back(), std::nullopt);
    EXPECT_NEAR(s.curve_y.back(), end.drawbar_pull, 1e-9);
  }
  EXPECT_EQ(drawn, 80u);
  // At one slip angle the residuals are drawn against slip, not in one vertical line.
  ASSERT_TRUE(f.residuals);
  EXPECT_EQ(f.residuals->x_title, "slip");
  std::set<double> xs;
  for (const auto& s : f.residuals->rows.at(0).panels.at(0).series) xs.insert(s.x.begin(), s.x.end());
  EXPECT_EQ(xs.size(), 8u);  // the 8 slips -0.2 .. 0.5 (the two-load wheel's among them)
  EXPECT_NEAR(*xs.begin(), -0.2, 1e-12);
  EXPECT_NEAR(*xs.rbegin(), 0.5, 1e-12);
}

TEST(LabFigures, ResidualsAgainstSlipAngleAreMeasuredMinusPredictedPerPoint) {
  TempDir dir;
  const std::string csv = dir.file("angles.csv");
  write_text(csv, model_rows());
  const app::ViewInput in = app::load_view_input(csv, std::nullopt, {});
  const views::LabFigures f = app::lab_figures_of(in, std::nullopt);
  ASSERT_TRUE(f.residuals);
  const views::PanelFigure& res = *f.residuals;
  EXPECT_EQ(res.x_title, "slip angle (deg)");
  ASSERT_EQ(res.rows.size(), 2u);
  for (std::size_t row = 0; row < 2; ++row) {
    EXPECT_EQ(res.rows[row].y_title, "measured - predicted (N)");
    ASSERT_EQ(res.rows[row].panels.size(), 1u);
    const auto& series = res.rows[row].panels[0].series;
    ASSERT_EQ(series.size(), 2u);  // the grey zero line with its band, then the wheel's points
    EXPECT_EQ(series[0].group, -1);
    EXPECT_NEAR(series[0].band, row == 0 ? 2.0 : 0.0, 1e-6);
    ASSERT_EQ(series[1].x.size(), 15u);
    for (std::size_t i = 0; i < 15; ++i) {
      EXPECT_DOUBLE_EQ(series[1].x[i], in.wheel_points[i].slip_angle * 180.0 / M_PI);
      EXPECT_NEAR(series[1].y[i], row == 0 ? kOffset : 0.0, 1e-6);
    }
  }
}

TEST(LabFigures, TheStudysFinalModelIsDrawnWithItsHeldOutBand) {
  TempDir dir;
  const std::string csv = dir.file("angles.csv");
  write_text(csv, model_rows());
  const app::ViewInput in = app::load_view_input(csv, std::nullopt, {});
  // A study's result as study_single_wheel returns it: a chain whose fit moved the cohesion.
  analysis::DiscrepancyReport r;
  r.baseline_model = "Ishigami (slip angle)";
  r.slip_definition = "travel";
  r.final_model = "soil-strength";
  r.held_out_method = "leave-one-out";
  analysis::CandidateResult c;
  c.name = "soil-strength";
  c.fit.soil = dry_sand();
  c.fit.soil.cohesion += 500.0;
  for (std::size_t i = 0; i < in.wheel_points.size(); ++i) {
    c.held_out.push_back({i, Quantity::drawbar_pull, 3.0, i % 2 == 0 ? 0.0 : 6.0, 0.5});  // RMS 3 N
  }
  r.selection.push_back(c);
  const app::SingleWheelModel m = app::final_single_wheel_model(dry_sand(), in.wheel_points, r);
  EXPECT_EQ(m.model.soil.cohesion, dry_sand().cohesion + 500.0);
  EXPECT_EQ(m.model.options.slip_definition, terramechanics::SlipDefinition::travel);
  const views::LabFigures f = app::single_wheel_figures(in.wheel_points, m);
  ASSERT_TRUE(f.slip_panels);
  EXPECT_NE(f.slip_panels->caption.find("final model"), std::string::npos) << f.slip_panels->caption;
  EXPECT_NE(f.slip_panels->caption.find("leave-one-out"), std::string::npos) << f.slip_panels->caption;
  const views::PanelSeries& s = f.slip_panels->rows[0].panels[0].series[0];
  EXPECT_NEAR(s.band, 6.0, 1e-12);
  terramechanics::GridModel fitted = m.model;
  fitted.wheel = in.wheel_points.front().wheel;  // the curves are drawn at the file's wheel
  const auto t = terramechanics::model_at(fitted, 20.0, s.curve_x.back(), 0.0);
  EXPECT_EQ(s.curve_y.back(), t.drawbar_pull);  // the fitted soil's curve, not the baseline's
  EXPECT_NE(s.curve_y.back(),
            terramechanics::model_at(truth(terramechanics::SlipDefinition::travel), 20.0, s.curve_x.back(), 0.0)
                .drawbar_pull);
}

TEST(LabFigures, ALogHasNoneAndTheViewsSayWhy) {
  TempDir dir;
  const std::string csv = dir.file("log.csv");
  write_text(csv, "time [s],x [m]\n0,1\n1,2\n");
  const app::ViewInput in = app::load_view_input(csv, std::nullopt, {});
  const views::View* view = views::find_view("slip-panels");
  ASSERT_NE(view, nullptr);
  EXPECT_TRUE(view->uses_lab_figures());
  try {
    app::scene_input(in, *view, {});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not a single-wheel test table"), std::string::npos) << e.what();
  }
}

// A plate pushed 4 cm into a Bekker soil and withdrawn (no noise): its force
// against depth in mm, the virgin loading apart, and the three fitted curves,
// Bekker's through the truth.
TEST(LabFigures, PlateForceAgainstDepthHoldsTheSamplesAndTheFittedCurves) {
  TempDir dir;
  const std::string csv = dir.file("plate.csv");
  const double b = 0.05, area = M_PI * 0.1 * 0.1 / 4;
  std::string rows = "# plate_diameter_m: 0.1\ndepth_m,force_N\n";
  std::size_t loading = 0;
  const auto force = [&](double z) {
    return z > 0 ? area * terramechanics::bekker_pressure(15600, 2.4e6, 1.1, b, z) : 0.0;
  };
  for (int i = -50; i <= 200; ++i) {  // down to 40 mm
    const double z = i * 2e-4;
    rows += std::to_string(z) + "," + std::to_string(force(z) + 0.3 * ((i % 3) - 1)) + "\n";
    loading += z > 0 ? 1 : 0;
  }
  for (int i = 199; i >= 150; --i) rows += std::to_string(i * 2e-4) + ",0\n";  // lifted off: no force
  write_text(csv, rows);
  const app::ViewInput in = app::load_view_input(csv, std::nullopt, {});
  ASSERT_TRUE(in.is_plate_test());
  const views::LabFigures f = app::lab_figures_of(in, std::nullopt);
  ASSERT_TRUE(f.force_depth);
  EXPECT_FALSE(f.slip_panels);
  const views::PanelFigure& p = *f.force_depth;
  EXPECT_EQ(p.x_title, "depth (mm)");
  ASSERT_EQ(p.rows.size(), 1u);
  EXPECT_EQ(p.rows[0].y_title, "force (N)");
  ASSERT_EQ(p.rows[0].panels.size(), 1u);
  const views::Panel& panel = p.rows[0].panels[0];
  EXPECT_EQ(panel.title, "plate of diameter 100 mm");
  ASSERT_EQ(panel.series.size(), 5u);  // the other samples, the virgin loading, Bekker, Reece, RFT
  EXPECT_EQ(panel.series[0].x.size() + panel.series[1].x.size(), 251u + 50u);
  EXPECT_NEAR(static_cast<double>(panel.series[1].x.size()), static_cast<double>(loading), 5.0);
  EXPECT_NEAR(*std::max_element(panel.series[1].x.begin(), panel.series[1].x.end()), 40.0, 0.25);  // in mm
  ASSERT_EQ(p.group_names.size(), 5u);
  EXPECT_EQ(p.group_names[2].rfind("Bekker", 0), 0u);
  const views::PanelSeries& bekker = panel.series[2];
  EXPECT_EQ(bekker.group, 2);
  ASSERT_FALSE(bekker.curve_x.empty());
  for (std::size_t i = 0; i < bekker.curve_x.size(); ++i) {
    if (bekker.curve_x[i] > 1.0) {
      EXPECT_NEAR(bekker.curve_y[i], force(bekker.curve_x[i] / 1000.0), 2.0);
    }
  }
  const views::PanelRanges r = views::panel_ranges(p);
  EXPECT_LT(r.x_min, -10.0);
  EXPECT_GT(r.x_max, 40.0);
  EXPECT_GT(r.y_max[0], force(0.04));
}
