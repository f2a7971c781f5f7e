// What a field engineer tripped over (issue 48), read back from the widgets,
// the tables and the text: one meaning for bold in every result table, with
// a legend; headline numbers that carry the weakest slip class and say which
// frame their RMSE is in; labels that fit or elide visibly with a tooltip;
// defaults that match their help; a headless screenshot that leaves the
// user's settings file byte for byte as it was.
#include <gtest/gtest.h>

#include <QVTKOpenGLNativeWidget.h>
#include <vtkActor2DCollection.h>
#include <vtkChartXY.h>
#include <vtkOpenGLRenderWindow.h>
#include <vtkPlot.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <QApplication>
#include <QDockWidget>
#include <QElapsedTimer>
#include <QHeaderView>
#include <QLabel>
#include <QLayout>
#include <QStackedWidget>
#include <QStandardPaths>
#include <QSurfaceFormat>
#include <QTableWidget>
#include <QThread>
#include <QTreeWidget>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>

#include "app/analysis.h"
#include "app/gui/main_window.h"
#include "app/log_input.h"
#include "test_support.h"
#include "tests/support/gui_main.h"
#include "views/contact_angle_scene.h"
#include "views/timeseries_chart.h"
#include "views/x_display.h"

using namespace roverlab;
using namespace roverlab::test;

namespace {

const std::string kExe = ROVERLAB_EXE;
const std::string kData = ROVERLAB_TEST_DATA;
const std::string kPathfinder = kData + "/test17run.mat";

CommandResult run_roverlab(const std::string& args) { return run_command(quote(kExe) + " " + args); }

nlohmann::json json_of(const std::string& args) {
  const CommandResult r = run_roverlab(args + " --json");
  EXPECT_EQ(r.exit_code, 0) << args << ": " << r.err;
  return r.exit_code == 0 ? nlohmann::json::parse(r.out) : nlohmann::json();
}

bool open_and_wait(gui::MainWindow& w, const std::string& file) {
  w.set_quiet(true);
  w.show();
  w.open_file(QString::fromStdString(file));
  return wait_until([&] { return w.has_log(); }, 120000) && wait_until([&] { return !w.busy(); }, 300000) &&
         w.last_error().isEmpty();
}

// The bundled WVU log's results and a simulated rover study (soil strength
// 0.8 hidden), made once as a user makes them.
class Readability : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    const std::string run = dir_->file("run.h5");
    study_ = dir_->file("study.h5");
    const CommandResult sim = run_roverlab("simulate flat_60s --seed 3 --effect soil-strength=0.8 -o " + quote(run));
    ASSERT_EQ(sim.exit_code, 0) << sim.err;
    const CommandResult rover = run_roverlab("discrepancy rover " + quote(run) + " -o " + quote(study_));
    ASSERT_EQ(rover.exit_code, 0) << rover.err;
    rover_ = new nlohmann::json(json_of("discrepancy rover " + quote(study_)));
    odometry_ = new nlohmann::json(json_of("discrepancy odometry " + quote(kPathfinder) + " -m wvu_pathfinder"));
    ins_ = new nlohmann::json(json_of("estimate ins-slip " + quote(kPathfinder) + " -m wvu_pathfinder"));
  }
  static void TearDownTestSuite() {
    delete rover_;
    delete odometry_;
    delete ins_;
    delete dir_;
  }
  static inline TempDir* dir_ = nullptr;
  static inline std::string study_;
  static inline nlohmann::json *rover_ = nullptr, *odometry_ = nullptr, *ins_ = nullptr;
};

// The names a study's verdict gives as the cause.
std::vector<std::string> named_causes(const std::string& analysis, const nlohmann::json& doc) {
  std::vector<std::string> named;
  if (analysis == "odometry" && doc.at("cause").is_string()) named.push_back(doc.at("cause").get<std::string>());
  if (analysis == "rover-discrepancy") {
    for (const auto& c : doc.at("causes")) named.push_back(c.get<std::string>());
  }
  return named;
}

bool row_bold(const app::ResultTable& t, std::size_t i) {
  return std::any_of(t.rows[i].begin(), t.rows[i].end(), [](const app::ResultTable::Cell& c) { return c.bold; });
}

}  // namespace

// Bold is the cause the study names, in every table, and nothing else; each
// table has a legend line saying so. The rover study here has candidates that
// are significant but not named (slip-angle, grousers): they were bold before.
TEST_F(Readability, BoldIsTheNamedCauseInEveryTableAndALegendSaysSo) {
  std::size_t significant_not_named = 0, bold_rows = 0;
  for (const auto& [name, doc] : {std::pair<std::string, const nlohmann::json*>{"rover-discrepancy", rover_},
                                  {"odometry", odometry_},
                                  {"ins-slip", ins_}}) {
    const auto analysis = app::make_analysis(name);
    const std::vector<std::string> named = named_causes(name, *doc);
    for (const auto& c : doc->contains("candidates") ? doc->at("candidates") : nlohmann::json::array()) {
      const bool is_named = std::find(named.begin(), named.end(), c.at("name")) != named.end();
      if (c.contains("significant") && c.at("significant").get<bool>() && !is_named) ++significant_not_named;
    }
    for (const app::ResultTable& t : analysis->presentation().tables(*doc)) {
      EXPECT_FALSE(t.legend.empty()) << t.title;
      std::string legend = t.legend;
      std::transform(legend.begin(), legend.end(), legend.begin(), [](unsigned char ch) { return std::tolower(ch); });
      EXPECT_NE(legend.find("bold"), std::string::npos) << t.title << ": " << t.legend;
      for (std::size_t i = 0; i < t.rows.size(); ++i) {
        const bool is_named = t.title.find("candidate") != std::string::npos &&
                              std::find(named.begin(), named.end(), t.rows[i].front().text) != named.end();
        EXPECT_EQ(row_bold(t, i), is_named) << t.title << ": row " << t.rows[i].front().text;
        bold_rows += row_bold(t, i) ? 1 : 0;
      }
      // The report writes the same table with its legend under it.
      TempDir folder;
      app::ReportSection section(folder.path());
      section.table(t);
      const std::string html = section.html.str();
      EXPECT_NE(html.find("</table>\n<p class=\"legend\""), std::string::npos) << t.title;
      EXPECT_NE(html.find(app::ReportSection::escape(t.legend)), std::string::npos) << t.title;
    }
  }
  EXPECT_GE(significant_not_named, 1u);  // the case that read wrong before
  EXPECT_EQ(bold_rows, 2u);              // soil strength change (rover study) and turning track (odometry)
  EXPECT_EQ(rover_->at("causes"), nlohmann::json::array({"soil strength change"}));
}

// The GUI's Analysis pane: the candidate table's bold rows and its legend, read from the widgets.
TEST_F(Readability, TheAnalysisPaneBoldsOnlyTheNamedCauseWithTheLegendUnderTheTable) {
  gui::MainWindow w;
  ASSERT_TRUE(open_and_wait(w, study_)) << w.last_error().toStdString();
  const auto analysis = app::make_analysis("rover-discrepancy");
  const nlohmann::json* doc = w.input()->result("rover-discrepancy");
  ASSERT_NE(doc, nullptr);
  const app::ResultTable t = analysis->presentation().tables(*doc).front();
  const auto* table = w.findChild<QTableWidget*>(QString::fromStdString(t.title));
  ASSERT_NE(table, nullptr);
  int bold = 0;
  for (int i = 0; i < table->rowCount(); ++i) {
    const bool is_bold = table->item(i, 0)->font().bold();
    bold += is_bold ? 1 : 0;
    EXPECT_EQ(is_bold, table->item(i, 0)->text() == "soil strength change") << table->item(i, 0)->text().toStdString();
  }
  EXPECT_EQ(bold, 1);
  const auto* legend = w.findChild<QLabel*>(QString::fromStdString(t.title + " (legend)"));
  ASSERT_NE(legend, nullptr);
  EXPECT_EQ(legend->text().toStdString(), t.legend);
  EXPECT_NE(legend->text().indexOf("soil strength change"), -1);
  // Right under its table.
  ASSERT_NE(legend->parentWidget(), nullptr);
  const QLayout* column = legend->parentWidget()->layout();
  EXPECT_EQ(column->indexOf(const_cast<QLabel*>(legend)), column->indexOf(const_cast<QTableWidget*>(table)) + 1);
}

// The INS summary's headline carries the weakest slip class beside the
// accuracy and names its frame: horizontal, with the vertical RMSE beside.
// On WVU every reference "high" sample is classed "low".
TEST_F(Readability, TheInsSummaryCarriesTheWeakestClassAndNamesItsFrame) {
  const auto analysis = app::make_analysis("ins-slip");
  const std::string summary = analysis->presentation().summary(*ins_);
  // The weakest class, found here from the counts.
  const nlohmann::json& c = ins_->at("slip_confusion");
  std::string weakest;
  double lowest = 2.0;
  long weakest_samples = 0;
  for (std::size_t t = 0; t < c.at("classes").size(); ++t) {
    long column = 0;
    for (std::size_t e = 0; e < c.at("classes").size(); ++e) column += c.at("counts").at(e).at(t).get<long>();
    if (column == 0) continue;
    const double recall = static_cast<double>(c.at("counts").at(t).at(t).get<long>()) / static_cast<double>(column);
    if (recall < lowest) {
      lowest = recall;
      weakest = c.at("classes").at(t).get<std::string>();
      weakest_samples = column;
    }
  }
  EXPECT_EQ(weakest, "high");
  char expected[96];
  std::snprintf(expected, sizeof expected, "weakest class %s: recall %.1f %% of %ld sample", weakest.c_str(),
                100.0 * lowest, weakest_samples);
  EXPECT_NE(summary.find(expected), std::string::npos) << summary;
  char rmse[96];
  std::snprintf(rmse, sizeof rmse, "RMSE %.2f m horizontal (%.2f m vertical)",
                ins_->at("ins").at("position_rmse_m").get<double>(),
                ins_->at("ins").at("position_rmse_enu_m").at(2).get<double>());
  EXPECT_NE(summary.find(rmse), std::string::npos) << summary;
  EXPECT_GT(ins_->at("ins").at("position_rmse_enu_m").at(2).get<double>(), 5.0);  // the 5.91 m the summary hid
  // The text and the campaign's headings say it too.
  const std::string text = app::printed(*analysis, *ins_);
  EXPECT_NE(text.find("recall per reference class: none 100.0 %"), std::string::npos) << text;
  EXPECT_NE(text.find("horizontal"), std::string::npos);
  for (const app::KeyMetric& m : analysis->presentation().key_metrics()) {
    if (m.pointer.find("position") != std::string::npos) {
      EXPECT_NE(m.title.find("horizontal"), std::string::npos) << m.title;
    }
  }
}

// The Streams pane: every sample count whole, a long stream name elided in
// its middle with the whole name in its tooltip.
TEST_F(Readability, TheStreamsPaneShowsWholeCountsAndElidesNamesWithATooltip) {
  gui::MainWindow w;
  w.resize(1400, 900);
  ASSERT_TRUE(open_and_wait(w, study_)) << w.last_error().toStdString();
  const auto* tree = w.findChild<QTreeWidget*>();
  ASSERT_NE(tree, nullptr);
  EXPECT_EQ(tree->textElideMode(), Qt::ElideMiddle);
  const QFontMetrics fm(tree->font());
  bool long_name = false;
  for (int i = 0; i < tree->topLevelItemCount(); ++i) {
    const QTreeWidgetItem* item = tree->topLevelItem(i);
    EXPECT_EQ(item->toolTip(0), item->text(0));
    const int needed = fm.horizontalAdvance(item->text(2));
    EXPECT_GE(tree->header()->sectionSize(2), needed) << item->text(2).toStdString();
    long_name = long_name || fm.horizontalAdvance(item->text(0)) > tree->header()->sectionSize(0);
    for (int k = 0; k < item->childCount(); ++k) {
      EXPECT_EQ(item->child(k)->toolTip(0), item->text(0) + ":" + item->child(k)->text(0));
    }
  }
  EXPECT_TRUE(long_name);  // the estimate/rover_discrepancy/... names do not fit the column: elided, with tooltip
  // The dock's title is not cut off: it fits the dock, and the usage hint is the header's tooltip.
  const auto* dock = qobject_cast<const QDockWidget*>(tree->parentWidget());
  ASSERT_NE(dock, nullptr);
  EXPECT_LE(QFontMetrics(dock->font()).horizontalAdvance(dock->windowTitle()), dock->width());
  EXPECT_FALSE(tree->headerItem()->toolTip(0).isEmpty());
}

// A legend entry with no value at the cursor says so in words, never "= -".
TEST(ReadabilityViews, APlotLegendWithNoValueAtTheCursorSaysSo) {
  log::Log lg;
  std::vector<double> t0, t1, x, y;
  for (int i = 0; i <= 1000; ++i) {
    t0.push_back(0.01 * i);
    x.push_back(std::sin(0.01 * i));
  }
  for (int i = 0; i <= 500; ++i) {
    t1.push_back(5.0 + 0.01 * i);
    y.push_back(0.5);
  }
  log::Stream a("a", t0), b("b", t1);
  a.add_channel("x", "m", x);
  b.add_channel("y", "m", y);
  lg.add_stream(std::move(a));
  lg.add_stream(std::move(b));
  views::TimeSeriesChart chart(lg, {{"a", "x"}, {"b", "y"}});
  chart.set_cursor(2.0);
  std::vector<std::string> labels;
  for (std::size_t g = 0; g < chart.plot_count(); ++g) {
    for (vtkIdType k = 0; k < chart.chart(g)->GetNumberOfPlots(); ++k) {
      const vtkStdString label = chart.chart(g)->GetPlot(k)->GetLabel();
      if (label.rfind("a:x", 0) == 0 || label.rfind("b:y", 0) == 0) labels.emplace_back(label);  // the curves
    }
  }
  ASSERT_EQ(labels.size(), 2u);
  for (const auto& l : labels) EXPECT_EQ(l.find("= -"), std::string::npos) << l;
  const auto ends_with = [](const std::string& s, const std::string& tail) {
    return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
  };
  EXPECT_EQ(std::count_if(labels.begin(), labels.end(),
                          [&](const std::string& l) { return ends_with(l, "(no value at the cursor)"); }),
            1);
  char value[32];
  std::snprintf(value, sizeof value, " = %.4g", std::sin(2.0));
  EXPECT_EQ(std::count_if(labels.begin(), labels.end(), [&](const std::string& l) { return ends_with(l, value); }), 1);
  // The cursor starts mid-log, as render --help says.
  EXPECT_DOUBLE_EQ(chart.default_time(), 5.0);
}

// The contact-angle panels: a truth of -0.0001 rad reads "0.0", not "-0.0",
// and the first panel says which arrow is which.
TEST(ReadabilityViews, ContactAnglePanelsSayWhichArrowIsWhichAndNeverMinusZero) {
  log::Log lg;
  std::vector<double> t;
  for (int i = 0; i <= 200; ++i) t.push_back(0.01 * i);
  log::Stream est("estimate/contact/wheels", t), truth("truth/wheels", t);
  for (const char* w : {"FL", "FR"}) {
    est.add_channel(std::string("contact_angle_") + w, "rad", std::vector<double>(t.size(), 0.2));
    est.add_channel(std::string("side_slip_") + w, "rad", std::vector<double>(t.size(), 0.0));
    truth.add_channel(std::string("contact_angle_") + w, "rad", std::vector<double>(t.size(), -1e-4));
    truth.add_channel(std::string("side_slip_") + w, "rad", std::vector<double>(t.size(), -1e-4));
  }
  lg.add_stream(std::move(est));
  lg.add_stream(std::move(truth));
  views::ContactAngleScene scene(lg);
  scene.set_time(1.0);
  std::vector<std::string> texts;
  for (const auto& r : scene.renderers()) {
    vtkActor2DCollection* actors = r->GetActors2D();
    actors->InitTraversal();
    while (vtkActor2D* a = actors->GetNextActor2D()) {
      if (auto* text = vtkTextActor::SafeDownCast(a); text != nullptr && text->GetInput() != nullptr)
        texts.emplace_back(text->GetInput());
    }
  }
  ASSERT_EQ(texts.size(), 2u);
  for (const auto& text : texts) {
    EXPECT_EQ(text.find("-0.0"), std::string::npos) << text;
    EXPECT_NE(text.find("contact 11.5 deg (truth 0.0)"), std::string::npos) << text;
  }
  EXPECT_NE(texts.front().find("arrows: blue estimate, green truth"), std::string::npos) << texts.front();
}

// `render --view timeseries` shows the time its --help promises: mid-log.
TEST(ReadabilityViews, RenderTimeseriesShowsMidLogAsItsHelpSays) {
  const CommandResult help = run_roverlab("render --help");
  ASSERT_NE(help.out.find("default: mid-log"), std::string::npos) << help.out;
  TempDir dir;
  const CommandResult r = run_roverlab("render " + quote(kPathfinder) + " -m wvu_pathfinder --view timeseries -o " +
                                       quote(dir.file("plot.png")));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto at = r.out.find(", t = ");
  ASSERT_NE(at, std::string::npos) << r.out;
  const double shown = std::stod(r.out.substr(at + 6));
  const io::LoadedLog wvu = app::load_input(kPathfinder, std::string("wvu_pathfinder"));
  double start = HUGE_VAL, end = -HUGE_VAL;
  for (const auto& s : wvu.log.streams()) {
    if (s.empty()) continue;
    start = std::min(start, s.start_time());
    end = std::max(end, s.end_time());
  }
  EXPECT_NEAR(shown, 0.5 * (start + end), 0.006);
  EXPECT_GT(shown, start + 10.0);
}

// The Traction surface pane on a log with no traction data: the reason in
// words, whole and word-wrapped, where a black canvas was.
TEST_F(Readability, TheTractionSurfacePaneSaysWhyInFullWhereTheCanvasWasBlack) {
  gui::MainWindow w;
  w.resize(1400, 900);
  ASSERT_TRUE(open_and_wait(w, kPathfinder)) << w.last_error().toStdString();
  ASSERT_TRUE(w.select_tab("Traction surface"));
  QCoreApplication::processEvents();
  const QString note = w.pane_note("Traction surface");
  EXPECT_TRUE(note.startsWith("Nothing to draw in Traction surface: ")) << note.toStdString();
  QDockWidget* dock = w.pane("Traction surface");
  ASSERT_NE(dock, nullptr);
  const QLabel* shown = nullptr;
  for (const QLabel* l : dock->findChildren<QLabel*>()) {
    if (l->text() == note && l->isVisible()) shown = l;
  }
  ASSERT_NE(shown, nullptr);
  EXPECT_TRUE(shown->wordWrap());
  EXPECT_GE(shown->width(), 200);
  for (const auto* vtk : dock->findChildren<QVTKOpenGLNativeWidget*>()) EXPECT_FALSE(vtk->isVisible());
}

// `roverlab gui FILE --screenshot PNG` is a batch run: the user's settings
// (recent files, last folder, window arrangement) stay byte for byte as they were.
TEST(ReadabilityViews, AHeadlessScreenshotLeavesTheUsersSettingsFileAsItWas) {
  TempDir dir;
  const std::filesystem::path config = dir.file("config");
  std::filesystem::create_directories(config / "RoverLab");
  const std::string settings = (config / "RoverLab" / "RoverLab.conf").string();
  const std::string before = "[files]\nlast_dir=/home/engineer/field-2026\nrecent=/home/engineer/field-2026/day3.h5\n";
  write_text(settings, before);
  const std::string png = dir.file("shot.png");
  const CommandResult r = run_command("XDG_CONFIG_HOME=" + quote(config.string()) + " " + quote(kExe) + " gui " +
                                      quote(kPathfinder) + " --screenshot " + quote(png) + " --width 800 --height 600");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  ASSERT_TRUE(std::filesystem::exists(png));
  EXPECT_EQ(read_text(settings), before);
  // And none is made where there was none.
  std::filesystem::remove(settings);
  const CommandResult again =
      run_command("XDG_CONFIG_HOME=" + quote(config.string()) + " " + quote(kExe) + " gui " + quote(kPathfinder) +
                  " --screenshot " + quote(png) + " --width 800 --height 600");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_FALSE(std::filesystem::exists(settings));
}

int main(int argc, char** argv) { return roverlab::test::run_gui_tests(argc, argv); }
