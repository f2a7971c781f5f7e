// The main window under Xvfb (a private one when DISPLAY is unset): open the
// bundled log, scrub the timeline and see the rover move; the event loop never
// stalls while a job runs; closing during a job cancels it; a corrupt file
// gives a one-line error dialog and leaves the session usable.
#include <gtest/gtest.h>

#include <QVTKOpenGLNativeWidget.h>
#include <vtkAxis.h>
#include <vtkChartXY.h>
#include <vtkOpenGLRenderWindow.h>
#include <QAction>
#include <QApplication>
#include <QDockWidget>
#include <QDragEnterEvent>
#include <QElapsedTimer>
#include <QMessageBox>
#include <QMimeData>
#include <QScreen>
#include <QSettings>
#include <QStackedWidget>
#include <QStandardPaths>
#include <QSurfaceFormat>
#include <QTableWidget>
#include <QThread>
#include <QTimer>
#include <QTreeWidget>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <functional>
#include <set>
#include <thread>

#include "app/analysis.h"
#include "app/gui/main_window.h"
#include "app/resources.h"
#include "core/common/error.h"
#include "core/estimation/contact_angle/model_selection.h"
#include "core/estimation/ins_slip/ins_slip.h"
#include "core/simulation/flying_rover.h"
#include "core/simulation/skid_steer_scenario.h"
#include "importers/hdf5_log.h"
#include "importers/rover_file.h"
#include "test_support.h"
#include "tests/support/gui_main.h"
#include "views/rover_scene.h"
#include "views/timeseries_chart.h"
#include "views/x_display.h"

using namespace roverlab;
using namespace roverlab::test;

namespace {

const QString kPathfinder = QString(ROVERLAB_TEST_DATA) + "/test17run.mat";

bool wait_idle(gui::MainWindow& w, int timeout_ms = 60000) {
  return wait_until([&] { return !w.busy(); }, timeout_ms);
}

}  // namespace

TEST(Gui, OpenTheBundledLogScrubTheTimelineAndSeeTheRoverMove) {
  gui::MainWindow w;
  w.set_quiet(true);
  w.show();
  w.open_file(kPathfinder);
  ASSERT_TRUE(wait_until([&] { return w.has_log(); }, 60000));
  ASSERT_TRUE(wait_idle(w)) << "the estimator job did not finish";
  ASSERT_TRUE(w.last_error().isEmpty()) << w.last_error().toStdString();
  // Estimates arrived as new streams.
  EXPECT_NE(w.input()->log.find_stream("estimate/ins/pose"), nullptr);
  EXPECT_NE(w.input()->log.find_stream("estimate/ins/slip"), nullptr);
  EXPECT_EQ(w.rover_scene()->pose_source(), "estimate/ins/pose");
  // The Analysis tab holds the analyses' result documents: the figures
  // `estimate ins-slip --json` and `discrepancy odometry --json` print.
  const nlohmann::json* ins = w.input()->result("ins-slip");
  const nlohmann::json* odometry = w.input()->result("odometry");
  ASSERT_NE(ins, nullptr);
  ASSERT_NE(odometry, nullptr);
  EXPECT_LT(ins->at("ins").at("final_position_error_m").get<double>(),
            0.3 * ins->at("wheel_odometry").at("final_position_error_m").get<double>());
  EXPECT_EQ(ins->at("initial_heading").at("method"), "aligned");
  EXPECT_EQ(odometry->at("cause"), "turning track");
  w.select_tab("Rover");
  w.set_time(10.0);
  w.render_now();
  const Eigen::Vector3d a = w.rover_scene()->rover_position();
  const QImage at10 = w.grab().toImage();
  w.set_time(40.0);
  w.render_now();
  const Eigen::Vector3d b = w.rover_scene()->rover_position();
  const QImage at40 = w.grab().toImage();
  EXPECT_NEAR(w.current_time(), 40.0, 1e-9);
  // 30 s north at about 0.7 m/s.
  EXPECT_GT(b.y() - a.y(), 15.0);
  EXPECT_LT(b.y() - a.y(), 30.0);
  EXPECT_NE(at10, at40);  // the picture follows the timeline
  // Playing moves the time forward.
  w.set_time(20.0);
  QMetaObject::invokeMethod(
      &w, [&] {}, Qt::QueuedConnection);
  double seen = 0.0;
  QObject::connect(&w, &gui::MainWindow::time_changed, [&](double t) { seen = t; });
  w.add_plot_channel("imu", "angular_rate_z");
  EXPECT_NE(w.chart(), nullptr);
  bool has = false;
  for (const auto& c : w.chart()->channels()) has = has || (c.stream == "imu" && c.channel == "angular_rate_z");
  EXPECT_TRUE(has);
  w.set_time(25.0);
  EXPECT_NEAR(seen, 25.0, 1e-9);
  w.close();
}

namespace {

// The time, ns, that the calling thread has waited on a run queue for a CPU
// (the second field of /proc/thread-self/schedstat), or -1 where the kernel
// does not say.
long long run_queue_wait_ns() {
  std::ifstream f("/proc/thread-self/schedstat");
  long long on_cpu = 0, waited = -1;
  if (!(f >> on_cpu >> waited)) return -1;
  return waited;
}

// What the GUI thread met while a 10 ms timer scrubbed the timeline (a render
// on every tick) until `done` held (or timeout_ms passed), ms.
struct Scrubbing {
  int ticks = 0;
  qint64 longest_gap = 0;    // between two ticks, as the clock reads it
  qint64 longest_stall = 0;  // the same less the time the thread waited for a CPU
  qint64 scheduling = 0;     // a sleeping thread's longest gap meanwhile
};

// The longest gap between ticks is the stall a user sees, but at a load of 8
// on 2 cores most of it is the GUI thread waiting for a CPU, which no program
// can avoid. The stall less that wait (the run-queue time the kernel counts
// for the thread) is what the program itself holds the event loop for:
// rendering, waiting on the renderer and the X server, waiting on a lock. A
// thread that only sleeps 10 ms at a time measures the machine's scheduling
// delay meanwhile, which the renderer's threads and the X server meet too.
Scrubbing scrub_until(gui::MainWindow& w, const std::function<bool()>& done, int timeout_ms) {
  std::atomic<bool> stop{false};
  std::atomic<qint64> probe_worst{0};
  std::thread probe([&] {
    auto last = std::chrono::steady_clock::now();
    while (!stop.load()) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      const auto now = std::chrono::steady_clock::now();
      const qint64 gap = std::chrono::duration_cast<std::chrono::milliseconds>(now - last).count();
      probe_worst = std::max(probe_worst.load(), gap);
      last = now;
    }
  });
  Scrubbing out;
  QElapsedTimer clock;
  clock.start();
  qint64 last = clock.nsecsElapsed();
  long long last_wait = run_queue_wait_ns();
  QTimer tick;
  tick.setInterval(10);
  QObject::connect(&tick, &QTimer::timeout, [&] {
    const qint64 now = clock.nsecsElapsed();
    const long long wait = run_queue_wait_ns();
    const qint64 gap = now - last;
    const qint64 waited = (wait >= 0 && last_wait >= 0) ? std::clamp<qint64>(wait - last_wait, 0, gap) : 0;
    out.longest_gap = std::max(out.longest_gap, gap / 1000000);
    out.longest_stall = std::max(out.longest_stall, (gap - waited) / 1000000);
    last = now;
    last_wait = wait;
    ++out.ticks;
    w.set_time(w.start_time() + std::fmod(0.05 * out.ticks, w.end_time() - w.start_time()));
  });
  tick.start();
  wait_until(done, timeout_ms);
  tick.stop();
  stop = true;
  probe.join();
  out.scheduling = probe_worst.load();
  return out;
}

}  // namespace

// Issue 46: what the job adds to the GUI thread's longest stall, measured so
// that the machine's load does not decide it. The stall is the gap between
// ticks less the time the GUI thread waited for a CPU (scrub_until); it is
// compared with the same scrubbing with no job after the job, and with the
// scheduling delay a sleeping thread meets while the job runs (the job runs
// niced, JobRunner::kJobNice). On a quiet machine a rover frame under Xvfb
// (llvmpipe, 1024x640) takes about 25 ms and the limit is 100 ms; under load
// it is twice the larger of those plus 50 ms.
TEST(Gui, TheEventLoopNeverStallsWhileAJobRuns) {
  gui::MainWindow w;
  w.set_quiet(true);
  w.resize(1024, 640);
  w.show();
  w.open_file(kPathfinder);
  ASSERT_TRUE(wait_until([&] { return w.has_log(); }, 60000));
  ASSERT_TRUE(wait_idle(w));
  // A job of several estimator runs (about a second or more), while the GUI
  // scrubs the timeline and renders on every tick of a 10 ms timer.
  const log::Log* lg = &w.input()->log;
  std::atomic<int> runs{0};
  double last_progress = 0.0;
  QObject::connect(&w.jobs(), &gui::JobRunner::progress, [&](double f) { last_progress = std::max(last_progress, f); });
  ASSERT_TRUE(w.jobs().start("load test", [lg, &runs](const gui::JobControl& c) -> std::function<void()> {
    for (int k = 0; k < 3; ++k) {
      estimation::InsSlipOptions o;
      o.progress = [&](double f) {
        c.report((k + f) / 3.0);
        c.check();
      };
      estimation::run_ins_slip(*lg, o);
      ++runs;
    }
    return [] {};
  }));
  QElapsedTimer job_time;
  job_time.start();
  const Scrubbing with_job = scrub_until(
      w, [&] { return !w.busy(); }, 120000);
  const int job_ms = static_cast<int>(job_time.elapsed());
  ASSERT_FALSE(w.busy());
  EXPECT_EQ(runs.load(), 3);
  EXPECT_GT(with_job.ticks, 20);
  EXPECT_GT(last_progress, 0.5);
  // The same scrubbing for as long again (the longest stall grows with the
  // time watched), no job.
  const Scrubbing idle = scrub_until(
      w, [] { return false; }, std::clamp(job_ms, 1000, 60000));
  EXPECT_GT(idle.ticks, 20);
  const qint64 limit = std::max<qint64>(100, 2 * std::max(idle.longest_stall, with_job.scheduling) + 50);
  EXPECT_LT(with_job.longest_stall, limit)
      << "longest stall of the GUI thread with the job (gap between 10 ms ticks less its wait for a CPU), ms; "
      << "without: " << idle.longest_stall
      << " ms; a sleeping thread's longest gap while the job ran: " << with_job.scheduling
      << " ms; longest gaps as the clock reads them: " << with_job.longest_gap << " and " << idle.longest_gap << " ms";
  RecordProperty("longest_event_loop_stall_ms", static_cast<int>(with_job.longest_stall));
  RecordProperty("longest_event_loop_gap_ms", static_cast<int>(with_job.longest_gap));
  RecordProperty("longest_idle_stall_ms", static_cast<int>(idle.longest_stall));
  RecordProperty("longest_scheduling_gap_ms", static_cast<int>(with_job.scheduling));
}

TEST(Gui, ClosingTheWindowWhileAJobRunsCancelsIt) {
  auto* w = new gui::MainWindow;
  w->set_quiet(true);
  w->show();
  std::atomic<bool> applied{false}, stopped{false};
  ASSERT_TRUE(w->jobs().start("endless", [&](const gui::JobControl& c) -> std::function<void()> {
    try {
      for (int i = 0; i < 60000; ++i) {  // at most a minute
        c.check();
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
    } catch (const gui::Cancelled&) {
      stopped = true;
      throw;
    }
    return [&] { applied = true; };
  }));
  QElapsedTimer clock;
  clock.start();
  w->close();
  EXPECT_LT(clock.elapsed(), 2000);
  EXPECT_TRUE(stopped.load());
  EXPECT_FALSE(w->jobs().busy());
  delete w;
  EXPECT_FALSE(applied.load());
}

TEST(Gui, ACorruptFileGivesAOneLineErrorDialogAndTheSessionStaysUsable) {
  TempDir dir;
  write_text(dir.file("broken.h5"), "\x89HDF\r\n\x1a\n this is not really HDF5");
  gui::MainWindow w;
  w.show();
  QString dialog_text;
  QTimer closer;
  closer.setInterval(50);
  QObject::connect(&closer, &QTimer::timeout, [&] {
    if (auto* box = qobject_cast<QMessageBox*>(QApplication::activeModalWidget())) {
      dialog_text = box->text();
      box->accept();
    }
  });
  closer.start();
  w.open_file(QString::fromStdString(dir.file("broken.h5")));
  ASSERT_TRUE(wait_until([&] { return !dialog_text.isEmpty(); }, 30000));
  closer.stop();
  EXPECT_TRUE(dialog_text.contains("broken.h5")) << dialog_text.toStdString();
  EXPECT_FALSE(dialog_text.contains('\n')) << dialog_text.toStdString();
  EXPECT_FALSE(w.has_log());
  // Still usable: the bundled log opens.
  w.set_quiet(true);
  w.open_file(kPathfinder);
  ASSERT_TRUE(wait_until([&] { return w.has_log(); }, 60000));
  ASSERT_TRUE(wait_idle(w));
  EXPECT_NE(w.input()->log.find_stream("imu"), nullptr);
}

int main(int argc, char** argv) { return roverlab::test::run_gui_tests(argc, argv); }

TEST(Gui, TheContactAngleModelIsNamedAndTheAnalysisMenuSwitchesIt) {
  // A flying-rover FL-bogie log (100 Hz): opened, the estimator runs with
  // --model auto and the streams name the model the data chose; the menu's
  // C+SS runs it again with that model, which replaces the streams.
  TempDir dir;
  const std::string file = dir.file("fl.h5");
  {
    const auto rover = *io::find_rover("exomars_bb2", app::resource_subfolders("rovers")).dh;
    auto sc = simulation::flying_rover_scenario("fl-bogie-rotation", rover);
    sc.rate = 100.0;
    log::Log lg = simulation::simulate_flying_rover(rover, sc);
    lg.metadata.rover_id = "exomars_bb2";
    io::write_hdf5_log(lg, file);
  }
  gui::MainWindow w;
  w.set_quiet(true);
  w.show();
  w.open_file(QString::fromStdString(file));
  ASSERT_TRUE(wait_until([&] { return w.has_log(); }, 60000));
  ASSERT_TRUE(wait_until([&] { return w.input()->log.find_stream("estimate/contact/wheels") != nullptr; }, 120000));
  ASSERT_TRUE(wait_idle(w));
  const auto label = [&] { return estimation::model_label(w.input()->log.stream("estimate/contact/wheels")); };
  EXPECT_NE(label().find("chosen by the data"), std::string::npos) << label();
  const nlohmann::json* doc = w.input()->result("contact-angle");
  ASSERT_NE(doc, nullptr);
  EXPECT_EQ(doc->at("model_selection").at("candidates").size(), 3u);
  QAction* css = nullptr;
  for (QAction* a : w.findChildren<QAction*>()) {
    if (a->text() == "C+SS") css = a;
  }
  ASSERT_NE(css, nullptr);
  css->trigger();
  ASSERT_TRUE(wait_until([&] { return label().rfind("model c+ss, set by hand", 0) == 0; }, 120000)) << label();
  ASSERT_TRUE(wait_idle(w));
  EXPECT_NE(w.input()->log.stream("estimate/contact/wheels").find_channel("side_slip_FL"), nullptr);
  EXPECT_EQ(w.input()->result("contact-angle")->at("model"), "c+ss");
}

// One answer per question (issue 30): each analysis run on the same log
// through the command line (`estimate X --json`), the report (metrics.json)
// and the GUI's own job gives the same result document, settings included.
// Three logs cover the five analyses: a BB2 flying-rover run (contact
// angles), the bundled WVU field log (INS slip, odometry study) and a
// simulated Kapvik run (net traction, rover study).
TEST(Gui, EveryAnalysisGivesTheSameResultOnTheCommandLineTheReportAndTheGui) {
  TempDir dir;
  const auto roverlab = [](const std::string& args) { return run_command(quote(ROVERLAB_EXE) + " " + args); };
  const std::string bb2 = dir.file("bb2.h5"), wvu = dir.file("wvu.h5"), planar = dir.file("planar.h5");
  {
    const auto rover = *io::find_rover("exomars_bb2", app::resource_subfolders("rovers")).dh;
    auto sc = simulation::flying_rover_scenario("rear-bogie-rotation", rover);
    sc.rate = 100.0;
    log::Log lg = simulation::simulate_flying_rover(rover, sc);
    lg.metadata.rover_id = "exomars_bb2";
    io::write_hdf5_log(lg, bb2);
  }
  ASSERT_EQ(roverlab("convert " + quote(kPathfinder.toStdString()) + " " + quote(wvu) + " --mapping wvu_pathfinder")
                .exit_code,
            0);
  ASSERT_EQ(roverlab("simulate flat_60s -o " + quote(planar)).exit_code, 0);
  std::set<std::string> compared, with_tables;
  for (const std::string& file : {bb2, wvu, planar}) {
    const std::string folder = dir.file("report_" + std::to_string(compared.size()));
    const CommandResult report = roverlab("report " + quote(file) + " -o " + quote(folder));
    ASSERT_EQ(report.exit_code, 0) << report.err;
    const nlohmann::json metrics = nlohmann::json::parse(read_text(folder + "/metrics.json"));
    gui::MainWindow w;
    w.set_quiet(true);
    w.show();
    w.open_file(QString::fromStdString(file));
    ASSERT_TRUE(wait_until([&] { return w.has_log(); }, 60000));
    ASSERT_TRUE(wait_idle(w, 300000));
    for (const auto& [name, from_report] : metrics.at("analyses").items()) {
      const std::unique_ptr<app::Analysis> a = app::make_analysis(name);
      ASSERT_NE(a, nullptr) << name;
      const CommandResult cli = roverlab(a->identity().command + " " + quote(file) + " --json");
      ASSERT_EQ(cli.exit_code, 0) << cli.err;
      const nlohmann::json from_cli = app::without_run_details(nlohmann::json::parse(cli.out));
      // The differences (JSON patch), not two whole documents, when they differ.
      EXPECT_EQ(nlohmann::json::diff(from_cli, app::without_run_details(from_report)), nlohmann::json::array())
          << name << " on " << file;
      const nlohmann::json* from_gui = w.input()->result(name);
      ASSERT_NE(from_gui, nullptr) << name << " did not run in the GUI on " << file;
      EXPECT_EQ(nlohmann::json::diff(from_cli, app::without_run_details(*from_gui)), nlohmann::json::array())
          << name << " on " << file;
      EXPECT_TRUE(from_cli.contains("configuration")) << name;
      // Its tables (Presentation::tables) in the Analysis pane, cell for cell.
      for (const app::ResultTable& t : a->presentation().tables(*from_gui)) {
        const auto* table = w.findChild<QTableWidget*>(QString::fromStdString(t.title));
        ASSERT_NE(table, nullptr) << t.title;
        ASSERT_EQ(table->rowCount(), static_cast<int>(t.rows.size())) << t.title;
        for (std::size_t i = 0; i < t.rows.size(); ++i) {
          for (std::size_t k = 0; k < t.columns.size(); ++k) {
            const QTableWidgetItem* item = table->item(static_cast<int>(i), static_cast<int>(k));
            ASSERT_NE(item, nullptr) << t.title;
            EXPECT_EQ(item->text().toStdString(), t.rows[i][k].text) << t.title << " row " << i;
          }
        }
        with_tables.insert(name);
      }
      compared.insert(name);
    }
  }
  for (const auto& a : app::all_analyses()) EXPECT_EQ(compared.count(a->name()), 1u) << a->name() << " not compared";
  // The slip-class confusion and the two studies' candidates are shown.
  for (const char* name : {"ins-slip", "odometry", "rover-discrepancy"}) EXPECT_EQ(with_tables.count(name), 1u) << name;
}

namespace {

std::string skid_steer_log(const TempDir& dir, const std::string& name, unsigned seed) {
  std::string file = dir.file(name);
  io::write_hdf5_log(simulation::simulate_skid_steer(simulation::default_slip_scenario(seed)), file);
  return file;
}

// Where a pane is in the window.
QRect in_window(const QWidget& w, const QWidget* pane) { return {pane->mapTo(&w, QPoint(0, 0)), pane->size()}; }

bool in_view(const QDockWidget* d) { return d->isVisible() && !d->visibleRegion().isEmpty(); }

}  // namespace

// Issue 32: the views are panes the user arranges. The map put beside the
// rover and a channel plotted on one log, saved as a layout, and the layout
// applied to another log with the same streams: the same panes side by side
// and the same channel plotted.
TEST(Gui, ALayoutSavedOnOneLogArrangesAnotherWithTheSameStreams) {
  TempDir dir;
  const std::string first = skid_steer_log(dir, "first.h5", 2), second = skid_steer_log(dir, "second.h5", 5);
  const std::string layout = dir.file("layout.json");
  QSettings().clear();  // a window restores the arrangement the last one closed with
  {
    gui::MainWindow w;
    w.set_quiet(true);
    w.show();
    w.open_file(QString::fromStdString(first));
    ASSERT_TRUE(wait_until([&] { return w.has_log(); }, 60000));
    ASSERT_TRUE(wait_idle(w, 120000));
    QDockWidget *rover = w.pane("Rover"), *map = w.pane("Map");
    ASSERT_NE(rover, nullptr);
    ASSERT_NE(map, nullptr);
    w.select_tab("Rover");
    // Tabbed together at first: only one of them in view.
    EXPECT_NE(in_view(rover), in_view(map));
    // As a user drags the map's tab out to the right of the others.
    w.removeDockWidget(map);
    w.addDockWidget(Qt::RightDockWidgetArea, map, Qt::Horizontal);
    map->show();
    w.add_plot_channel("imu", "angular_rate_z");
    w.select_tab("Rover");
    ASSERT_TRUE(wait_until([&] { return in_view(rover) && in_view(map); }, 5000));
    w.save_layout(QString::fromStdString(layout));
    w.close();
  }
  const auto doc = nlohmann::json::parse(read_text(layout));
  EXPECT_EQ(doc.at("format"), "roverlab-layout");
  // ROVERLAB_KEEP_LAYOUT=<file>: keep it (e.g. for `roverlab gui --layout FILE --screenshot`).
  if (const char* keep = std::getenv("ROVERLAB_KEEP_LAYOUT")) write_text(keep, read_text(layout));
  QSettings().clear();
  gui::MainWindow w;
  w.set_quiet(true);
  w.show();
  // A new window: tabbed as built.
  EXPECT_FALSE(in_view(w.pane("Rover")) && in_view(w.pane("Map")));
  w.apply_layout(QString::fromStdString(layout));
  w.open_file(QString::fromStdString(second));
  ASSERT_TRUE(wait_until([&] { return w.has_log(); }, 60000));
  ASSERT_TRUE(wait_idle(w, 120000));
  ASSERT_TRUE(wait_until([&] { return in_view(w.pane("Rover")) && in_view(w.pane("Map")); }, 5000));
  const QRect rover = in_window(w, w.pane("Rover")), map = in_window(w, w.pane("Map"));
  EXPECT_FALSE(rover.intersects(map)) << "side by side";
  EXPECT_GT(rover.width(), 150);
  EXPECT_GT(map.width(), 150);
  EXPECT_LE(rover.right(), map.left());  // the map right of the rover, as arranged
  ASSERT_NE(w.chart(), nullptr);
  bool plotted = false;
  for (const auto& c : w.chart()->channels()) plotted = plotted || (c.stream == "imu" && c.channel == "angular_rate_z");
  EXPECT_TRUE(plotted);
  EXPECT_EQ(w.input()->file, second);
  w.close();
  QSettings().clear();  // the next tests' windows start tabbed as built
  // Not a layout: one error naming the file.
  write_text(dir.file("bad.json"), "{\"format\": \"something else\"}");
  try {
    w.apply_layout(QString::fromStdString(dir.file("bad.json")));
    ADD_FAILURE() << "a file that is not a layout was applied";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
  }
}

// A pane whose view the log cannot feed says why in words (it was a black
// panel), and a long status line never widens the window (it grew to 2014 px).
TEST(Gui, APaneWithNothingToShowSaysWhyAndTheWindowNeverGrows) {
  TempDir dir;
  const std::string file = dir.file("flying.h5");
  {
    const auto rover = *io::find_rover("exomars_bb2", app::resource_subfolders("rovers")).dh;
    auto sc = simulation::flying_rover_scenario("fl-bogie-rotation", rover);
    sc.rate = 50.0;
    log::Log lg = simulation::simulate_flying_rover(rover, sc);
    lg.metadata.rover_id = "exomars_bb2";
    io::write_hdf5_log(lg, file);
  }
  gui::MainWindow w;
  w.set_quiet(true);
  w.resize(1000, 700);
  w.show();
  const int width = w.width();
  EXPECT_TRUE(w.pane_note("Map").contains("open a log")) << w.pane_note("Map").toStdString();
  w.open_file(QString::fromStdString(file));
  ASSERT_TRUE(wait_until([&] { return w.has_log(); }, 60000));
  ASSERT_TRUE(wait_idle(w, 120000));
  w.select_tab("Map");
  EXPECT_TRUE(w.pane_note("Map").contains("no position to map")) << w.pane_note("Map").toStdString();
  EXPECT_TRUE(w.pane_note("Rover").isEmpty()) << "the rover view draws this log";
  // The status line holds every note of the load (a long line): the window keeps its width.
  QCoreApplication::processEvents();
  EXPECT_EQ(w.width(), width);
  EXPECT_LE(w.width(), QGuiApplication::primaryScreen()->availableGeometry().width());
}

namespace {

// Sends `data` to `target` as a drag entering it and a drop; true when the drag was accepted.
bool drop_on(QWidget* target, QMimeData* data) {
  const QPoint at(target->width() / 2, target->height() / 2);
  QDragEnterEvent enter(at, Qt::CopyAction, data, Qt::LeftButton, Qt::NoModifier);
  QApplication::sendEvent(target, &enter);
  const bool accepted = enter.isAccepted();
  QDropEvent dropped(at, Qt::CopyAction, data, Qt::LeftButton, Qt::NoModifier);
  QApplication::sendEvent(target, &dropped);
  return accepted;
}

}  // namespace

// Issue 32: channels dragged from the streams tree onto the plot pane are
// plotted there: the tree's own drag data (its model's mime data for the
// items picked, as a drag carries it) dropped on the pane, through Qt's
// events; a stream dragged brings all its channels; other data is refused.
TEST(Gui, ChannelsDraggedFromTheStreamsTreeOntoThePlotPaneArePlotted) {
  TempDir dir;
  const std::string log = skid_steer_log(dir, "drag.h5", 3);
  QSettings().clear();
  gui::MainWindow w;
  w.set_quiet(true);
  w.show();
  w.open_file(QString::fromStdString(log));
  ASSERT_TRUE(wait_until([&] { return w.has_log(); }, 60000));
  ASSERT_TRUE(wait_idle(w, 120000));
  w.select_tab("Plots");
  QDockWidget* plots = w.pane("Plots");
  ASSERT_NE(plots, nullptr);
  auto* page = qobject_cast<QStackedWidget*>(plots->widget());
  ASSERT_NE(page, nullptr);
  QWidget* target = page->currentWidget();
  auto* tree = w.findChild<QTreeWidget*>();
  ASSERT_NE(tree, nullptr);
  const auto plotted = [&](const std::string& stream, const std::string& channel) {
    if (w.chart() == nullptr) return false;
    for (const auto& c : w.chart()->channels()) {
      if (c.stream == stream && c.channel == channel) return true;
    }
    return false;
  };
  const auto drag_of = [&](const QString& stream, const QString& channel) -> QMimeData* {
    const auto streams = tree->findItems(stream, Qt::MatchExactly, 0);
    if (streams.isEmpty()) return nullptr;
    QTreeWidgetItem* item = streams.front();
    for (int i = 0; !channel.isEmpty() && i < streams.front()->childCount(); ++i) {
      if (streams.front()->child(i)->text(0) == channel) item = streams.front()->child(i);
    }
    tree->setCurrentItem(item);
    return tree->model()->mimeData({tree->currentIndex()});
  };
  const auto drop = [&](QMimeData* data) { return drop_on(target, data); };
  ASSERT_FALSE(plotted("imu", "angular_rate_z"));
  std::unique_ptr<QMimeData> one(drag_of("imu", "angular_rate_z"));
  ASSERT_NE(one, nullptr);
  EXPECT_TRUE(one->hasFormat(gui::MainWindow::kChannelsMime));
  EXPECT_TRUE(drop(one.get()));
  EXPECT_TRUE(plotted("imu", "angular_rate_z"));
  // A whole stream: every channel of it.
  std::unique_ptr<QMimeData> stream(drag_of("wheels", ""));
  ASSERT_NE(stream, nullptr);
  EXPECT_TRUE(drop(stream.get()));
  const log::Stream* wheels = w.input()->log.find_stream("wheels");
  ASSERT_NE(wheels, nullptr);
  for (const auto& c : wheels->channels()) EXPECT_TRUE(plotted("wheels", c.name)) << c.name;
  // Plain text is not a channel: refused, nothing added.
  const std::size_t before = w.chart()->channels().size();
  QMimeData text;
  text.setText("imu\tspecific_force_x");
  EXPECT_FALSE(drop(&text));
  EXPECT_EQ(w.chart()->channels().size(), before);
  w.close();
  QSettings().clear();
}

namespace {

// The streams tree's own drag data for stream:channel (a whole stream when channel is empty).
QMimeData* tree_drag(gui::MainWindow& w, const QString& stream, const QString& channel) {
  auto* tree = w.findChild<QTreeWidget*>();
  const auto streams = tree->findItems(stream, Qt::MatchExactly, 0);
  if (streams.isEmpty()) return nullptr;
  QTreeWidgetItem* item = streams.front();
  for (int i = 0; !channel.isEmpty() && i < item->childCount(); ++i) {
    if (streams.front()->child(i)->text(0) == channel) item = streams.front()->child(i);
  }
  tree->setCurrentItem(item);
  return tree->model()->mimeData({tree->currentIndex()});
}

bool plots(const views::TimeSeriesChart* c, const std::string& stream, const std::string& channel) {
  if (c == nullptr) return false;
  const auto& all = c->channels();
  return std::any_of(all.begin(), all.end(), [&](const auto& r) { return r.stream == stream && r.channel == channel; });
}

QWidget* drop_target(QDockWidget* pane) { return qobject_cast<QStackedWidget*>(pane->widget())->currentWidget(); }

}  // namespace

// Issue 32: several plot panes side by side, each a drop target with its own
// channels; a layout records every plot pane with its channels and
// re-creates them on another log; the time window zoomed in one pane is
// followed by the other, whose value axis stays as the user set it.
TEST(Gui, PlotPanesSideBySideEachTakeTheirOwnDropsAndALayoutRecreatesThem) {
  TempDir dir;
  const std::string first = skid_steer_log(dir, "first.h5", 2), second = skid_steer_log(dir, "second.h5", 5);
  const std::string layout = dir.file("two-plots.json");
  QSettings().clear();
  int narrow = 0;
  {
    gui::MainWindow w;
    w.set_quiet(true);
    w.resize(1400, 900);
    w.show();
    w.open_file(QString::fromStdString(first));
    ASSERT_TRUE(wait_until([&] { return w.has_log(); }, 60000));
    ASSERT_TRUE(wait_idle(w, 120000));
    const int width = w.width();
    QDockWidget* second_pane = w.new_plot_pane();
    ASSERT_NE(second_pane, nullptr);
    EXPECT_EQ(second_pane->windowTitle(), "Plots 2");
    EXPECT_EQ(w.plot_pane_titles(), QStringList({"Plots", "Plots 2"}));
    // Empty until something is dropped on it, and it says so.
    EXPECT_TRUE(w.pane_note("Plots 2").contains("Drag channels")) << w.pane_note("Plots 2").toStdString();
    // (Qt lays a new dock out over a few turns of the event loop.)
    ASSERT_TRUE(wait_until(
        [&] { return in_view(w.pane("Plots")) && in_view(second_pane) && second_pane->width() > 300; }, 5000))
        << second_pane->width();
    const QRect a = in_window(w, w.pane("Plots")), b = in_window(w, second_pane);
    EXPECT_FALSE(a.intersects(b)) << "side by side";
    EXPECT_LE(a.right(), b.left());
    EXPECT_NEAR(a.width(), b.width(), 0.1 * b.width()) << "as wide as each other";
    // A channel dropped on the second pane is plotted there, not in the first.
    std::unique_ptr<QMimeData> rate(tree_drag(w, "imu", "angular_rate_z"));
    ASSERT_NE(rate, nullptr);
    EXPECT_TRUE(drop_on(drop_target(second_pane), rate.get()));
    EXPECT_TRUE(plots(w.chart("Plots 2"), "imu", "angular_rate_z"));
    EXPECT_FALSE(plots(w.chart("Plots"), "imu", "angular_rate_z"));
    EXPECT_TRUE(w.pane_note("Plots 2").isEmpty());
    // A whole stream dropped on the first: all of it there, none in the second.
    std::unique_ptr<QMimeData> wheels(tree_drag(w, "wheels", ""));
    EXPECT_TRUE(drop_on(drop_target(w.pane("Plots")), wheels.get()));
    const log::Stream* ws = w.input()->log.find_stream("wheels");
    ASSERT_NE(ws, nullptr);
    for (const auto& c : ws->channels()) {
      EXPECT_TRUE(plots(w.chart("Plots"), "wheels", c.name)) << c.name;
      EXPECT_FALSE(plots(w.chart("Plots 2"), "wheels", c.name)) << c.name;
    }
    ASSERT_EQ(w.chart("Plots 2")->channels().size(), 1u);
    // Linked zoom across panes: the second pane's value axis set by the user,
    // then the first pane's time axis moved: the second follows in time only.
    views::TimeSeriesChart *one = w.chart("Plots"), *two = w.chart("Plots 2");
    vtkAxis* values = two->chart(0)->GetAxis(vtkAxis::LEFT);
    values->SetRange(-0.01, 0.02);  // as a wheel or drag over it does
    ASSERT_TRUE(two->value_axis_set_by_user(0));
    const double t0 = w.start_time() + 5.0, t1 = w.start_time() + 9.0;
    one->chart(0)->GetAxis(vtkAxis::BOTTOM)->SetRange(t0, t1);
    EXPECT_DOUBLE_EQ(two->window().first, t0);
    EXPECT_DOUBLE_EQ(two->window().second, t1);
    EXPECT_DOUBLE_EQ(values->GetMinimum(), -0.01);
    EXPECT_DOUBLE_EQ(values->GetMaximum(), 0.02);
    // More panes never widen the window past the screen.
    w.new_plot_pane();
    w.new_plot_pane();
    QCoreApplication::processEvents();
    EXPECT_EQ(w.width(), width);
    EXPECT_LE(w.frameGeometry().width(), QGuiApplication::primaryScreen()->availableGeometry().width());
    EXPECT_TRUE(w.pane_note("Plots 4").contains("Drag channels"));
    // The user narrows Plots 2: the layout keeps it narrow.
    wait_until([] { return false; }, 300);
    w.resizeDocks({w.pane("Plots"), w.pane("Plots 2"), w.pane("Plots 3"), w.pane("Plots 4")}, {450, 120, 250, 250},
                  Qt::Horizontal);
    ASSERT_TRUE(wait_until([&] { return w.pane("Plots 2")->width() < 200; }, 3000)) << w.pane("Plots 2")->width();
    narrow = w.pane("Plots 2")->width();
    w.save_layout(QString::fromStdString(layout));
    w.close();
  }
  const auto doc = nlohmann::json::parse(read_text(layout));
  EXPECT_EQ(doc.at("version"), 2);
  ASSERT_EQ(doc.at("plot_panes").size(), 4u);
  if (const char* keep = std::getenv("ROVERLAB_KEEP_LAYOUT")) write_text(keep, read_text(layout));
  QSettings().clear();
  gui::MainWindow w;
  w.set_quiet(true);
  w.resize(1400, 900);
  w.show();
  EXPECT_EQ(w.plot_pane_titles(), QStringList({"Plots"}));
  w.apply_layout(QString::fromStdString(layout));
  EXPECT_EQ(w.plot_pane_titles(), QStringList({"Plots", "Plots 2", "Plots 3", "Plots 4"}));
  w.open_file(QString::fromStdString(second));
  ASSERT_TRUE(wait_until([&] { return w.has_log(); }, 60000));
  ASSERT_TRUE(wait_idle(w, 120000));
  ASSERT_TRUE(wait_until([&] { return in_view(w.pane("Plots")) && in_view(w.pane("Plots 2")); }, 5000));
  EXPECT_LE(in_window(w, w.pane("Plots")).right(), in_window(w, w.pane("Plots 2")).left());
  wait_until([] { return false; }, 300);  // (a new pane's row is shared out a turn later: not over the layout's)
  EXPECT_NEAR(w.pane("Plots 2")->width(), narrow, 20) << "as narrow as the layout has it";
  ASSERT_NE(w.chart("Plots 2"), nullptr);
  EXPECT_EQ(w.chart("Plots 2")->channels().size(), 1u);
  EXPECT_TRUE(plots(w.chart("Plots 2"), "imu", "angular_rate_z"));
  EXPECT_FALSE(plots(w.chart("Plots"), "imu", "angular_rate_z"));
  EXPECT_TRUE(plots(w.chart("Plots"), "wheels", w.input()->log.find_stream("wheels")->channels().front().name));
  EXPECT_TRUE(w.pane_note("Plots 3").contains("Drag channels"));
  EXPECT_EQ(w.input()->file, second);
  w.close();
  QSettings().clear();
}

// A version-1 layout (one "plots" list, before plot panes) is still read: its channels go to the Plots pane.
TEST(Gui, AVersionOneLayoutStillPlotsItsChannels) {
  TempDir dir;
  const std::string log = skid_steer_log(dir, "v1.h5", 4);
  QSettings().clear();
  std::string state;
  {
    gui::MainWindow w;
    state = w.saveState().toBase64().toStdString();
  }
  const nlohmann::json v1 = {{"format", "roverlab-layout"},
                             {"version", 1},
                             {"panes_in_front", {"Plots"}},
                             {"plots", {{{"stream", "imu"}, {"channel", "angular_rate_z"}}}},
                             {"window_state", state}};
  write_text(dir.file("v1.json"), v1.dump());
  gui::MainWindow w;
  w.set_quiet(true);
  w.show();
  w.apply_layout(QString::fromStdString(dir.file("v1.json")));
  w.open_file(QString::fromStdString(log));
  ASSERT_TRUE(wait_until([&] { return w.has_log(); }, 60000));
  ASSERT_TRUE(wait_idle(w, 120000));
  EXPECT_TRUE(plots(w.chart("Plots"), "imu", "angular_rate_z"));
  EXPECT_EQ(w.chart("Plots")->channels().size(), 1u);
  // A layout whose added pane asks for channels this log lacks: the pane names them.
  write_text(dir.file("lacks.json"), R"({"format": "roverlab-layout", "version": 2, "plot_panes": [
    {"name": "pane/timeseries", "channels": []},
    {"name": "pane/timeseries/2", "title": "Joints", "channels": [{"stream": "joints", "channel": "bogie"}]}]})");
  w.apply_layout(QString::fromStdString(dir.file("lacks.json")));
  EXPECT_TRUE(w.pane_note("Joints").contains("lacks the layout's channels for it (joints:bogie)"))
      << w.pane_note("Joints").toStdString();
  // A plot pane name that is not one: refused in one line naming the file.
  write_text(dir.file("bad.json"),
             R"({"format": "roverlab-layout", "version": 2, "plot_panes": [{"name": "../../x", "channels": []}]})");
  try {
    w.apply_layout(QString::fromStdString(dir.file("bad.json")));
    ADD_FAILURE() << "a layout with a bad pane name was applied";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
  }
  w.close();
  QSettings().clear();
}
