// File > Compare with... under Xvfb (issue 45): a simulated run and another
// seed of it with a hidden force-sensor offset. The second run's streams
// appear in the tree under its own name; the Compare tracks pane draws both
// runs' tracks (read back from the chart) with a marker on each at the
// timeline's time; the Compare runs pane draws the difference curve (run
// minus baseline on the baseline's times, read back from the chart) about
// the 0.5 N offset, with its noise band, and a compared channel
// double-clicked in the tree is drawn there.
#include <gtest/gtest.h>

#include <vtkChartXY.h>
#include <vtkPlot.h>
#include <vtkTable.h>
#include <vtkVariant.h>

#include <QTreeWidget>
#include <cmath>
#include <string>

#include "app/gui/main_window.h"
#include "importers/log_file.h"
#include "test_support.h"
#include "tests/support/gui_main.h"
#include "views/compare_chart.h"
#include "views/compare_map.h"

using namespace roverlab;
using namespace roverlab::test;

namespace {

std::string simulate(const TempDir& dir, unsigned seed, const std::string& effect) {
  std::string out = dir.file("run" + std::to_string(seed) + ".h5");
  const CommandResult r =
      run_command(quote(ROVERLAB_EXE) + " simulate flat_60s --duration 20 --seed " + std::to_string(seed) +
                  (effect.empty() ? "" : " --effect " + effect) + " -o " + quote(out));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return out;
}

bool wait_idle(gui::MainWindow& w) {
  return wait_until([&] { return !w.busy(); }, 60000);
}

}  // namespace

TEST(CompareGui, TheSecondRunsTracksAndDifferenceCurveAreDrawn) {
  TempDir dir;
  const std::string a = simulate(dir, 1, ""), b = simulate(dir, 3, "force-offset=0.5");
  const log::Log la = io::load_log(a).log, lb = io::load_log(b).log;
  gui::MainWindow w;
  w.set_quiet(true);
  w.resize(1200, 800);
  w.show();
  w.open_file(QString::fromStdString(a));
  ASSERT_TRUE(wait_until([&] { return w.has_log(); }, 60000));
  ASSERT_TRUE(wait_idle(w));
  EXPECT_EQ(w.pane_scene("Compare runs"), nullptr);  // nothing to compare yet: the pane says why
  EXPECT_NE(w.pane_note("Compare runs").indexOf("Compare with"), -1) << w.pane_note("Compare runs").toStdString();
  w.compare_with(QString::fromStdString(b));
  ASSERT_TRUE(wait_idle(w));
  ASSERT_TRUE(w.last_error().isEmpty()) << w.last_error().toStdString();
  ASSERT_EQ(w.compared_count(), 1u);

  // The tree: the run's streams under its own name.
  auto* tree = w.findChild<QTreeWidget*>();
  ASSERT_NE(tree, nullptr);
  const auto found = tree->findItems("run3 (compared)", Qt::MatchExactly);
  ASSERT_EQ(found.size(), 1);
  ASSERT_EQ(static_cast<std::size_t>(found.front()->childCount()), lb.streams().size());
  EXPECT_EQ(found.front()->child(0)->text(0).toStdString(), lb.streams().front().name());

  // The map: both tracks as drawn, each the run's own truth/pose, and each marker where its run is at the time.
  w.set_time(12.0);
  w.render_now();
  auto* map = dynamic_cast<views::CompareMap*>(w.pane_scene("Compare tracks"));
  ASSERT_NE(map, nullptr);
  ASSERT_EQ(map->track_count(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    const log::Stream& pose = (k == 0 ? la : lb).stream("truth/pose");
    auto* drawn = vtkTable::SafeDownCast(map->chart()->GetPlot(static_cast<vtkIdType>(2 * k))->GetInput());
    ASSERT_NE(drawn, nullptr);
    ASSERT_EQ(static_cast<std::size_t>(drawn->GetNumberOfRows()), pose.size());
    for (vtkIdType i = 0; i < drawn->GetNumberOfRows(); i += 97) {
      EXPECT_DOUBLE_EQ(drawn->GetValue(i, 0).ToDouble(), pose.channel("x").values[static_cast<std::size_t>(i)]);
      EXPECT_DOUBLE_EQ(drawn->GetValue(i, 1).ToDouble(), pose.channel("z").values[static_cast<std::size_t>(i)]);
    }
    EXPECT_NEAR(map->marker(k).x(), pose.value_at("x", 12.0), 1e-9);
    EXPECT_NEAR(map->marker(k).y(), pose.value_at("z", 12.0), 1e-9);
  }

  // The difference curve: its default channels are those the offset drives; every point drawn is the run minus
  // the baseline at a baseline time, about 0.5 N on average, outside the +-2 sigma band.
  auto* chart = dynamic_cast<views::CompareChart*>(w.pane_scene("Compare runs"));
  ASSERT_NE(chart, nullptr);
  ASSERT_FALSE(chart->channels().empty());
  EXPECT_EQ(chart->channels().front().stream, "forces");
  const std::string channel = chart->channels().front().channel;
  const log::Stream& fa = la.stream("forces");
  const log::Stream& fb = lb.stream("forces");
  auto* diff = vtkTable::SafeDownCast(chart->chart(1)->GetPlot(1)->GetInput());
  ASSERT_NE(diff, nullptr);
  ASSERT_GE(diff->GetNumberOfRows(), 200);
  double mean = 0;
  for (vtkIdType i = 0; i < diff->GetNumberOfRows(); ++i) {
    const double t = diff->GetValue(i, 0).ToDouble(), d = diff->GetValue(i, 1).ToDouble();
    ASSERT_NEAR(d, fb.value_at(channel, t) - fa.value_at(channel, t), 1e-9) << "t = " << t;
    mean += d / static_cast<double>(diff->GetNumberOfRows());
  }
  EXPECT_NEAR(mean, 0.5, 0.1);
  EXPECT_TRUE(chart->channel_comparison(0, 0).differs);
  EXPECT_GT(chart->band_half_width(0, 0), 0.0);
  EXPECT_LT(chart->band_half_width(0, 0), 0.4);
  EXPECT_NEAR(chart->difference_at_cursor(0, 0), fb.value_at(channel, 12.0) - fa.value_at(channel, 12.0), 1e-9);

  // A compared channel double-clicked in the tree is drawn in the Compare runs pane.
  QTreeWidgetItem* imu = nullptr;
  for (int i = 0; i < found.front()->childCount(); ++i) {
    if (found.front()->child(i)->text(0) == "imu") imu = found.front()->child(i);
  }
  ASSERT_NE(imu, nullptr);
  emit tree->itemDoubleClicked(imu->child(0), 0);
  chart = dynamic_cast<views::CompareChart*>(w.pane_scene("Compare runs"));
  ASSERT_NE(chart, nullptr);
  ASSERT_EQ(chart->channels().size(), 1u);
  EXPECT_EQ(chart->channels().front().channel, imu->child(0)->text(0).toStdString());
  EXPECT_FALSE(chart->channel_comparison(0, 0).differs);  // the IMU is not what the offset drives
  w.close();
}

int main(int argc, char** argv) { return run_gui_tests(argc, argv); }
