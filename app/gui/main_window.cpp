#include "app/gui/main_window.h"
#include "app/gui/layout_file.h"

#include <QVTKOpenGLNativeWidget.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkInteractorStyleRubberBand2D.h>
#include <vtkInteractorStyleTrackballCamera.h>
#include <vtkRenderWindowInteractor.h>
#include <CLI/CLI.hpp>
#include <QAction>
#include <QActionGroup>
#include <QApplication>
#include <QCloseEvent>
#include <QComboBox>
#include <QDateTime>
#include <QDockWidget>
#include <QDragEnterEvent>
#include <QDropEvent>
#include <QFile>
#include <QFileDialog>
#include <QFileInfo>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QLabel>
#include <QMenuBar>
#include <QMessageBox>
#include <QMimeData>
#include <QProgressBar>
#include <QPushButton>
#include <QScrollArea>
#include <QScrollBar>
#include <QSettings>
#include <QSlider>
#include <QStackedWidget>
#include <QStatusBar>
#include <QTabWidget>
#include <QTableWidget>
#include <QTimer>
#include <QToolBar>
#include <QToolButton>
#include <QTreeWidget>
#include <QVBoxLayout>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "app/analysis.h"
#include "app/lab_figures.h"
#include "app/resources.h"
#include "app/view_data.h"
#include "core/common/error.h"
#include "importers/atomic_file.h"
#include "importers/mapping.h"
#include "importers/rover_file.h"
#include "views/contact_angle_scene.h"
#include "views/rover_scene.h"
#include "views/timeseries_chart.h"
#include "views/view.h"

namespace roverlab::gui {

namespace {

constexpr int kSliderSteps = 10000;

QString q(const std::string& s) { return QString::fromStdString(s); }

// The streams tree, a drag source: the channels picked (a stream: all of
// its channels) as "stream<TAB>channel" lines under kChannelsMime, which a
// plot pane takes.
class StreamsTree : public QTreeWidget {
 public:
  StreamsTree() {
    setDragEnabled(true);
    setDragDropMode(QAbstractItemView::DragOnly);
    setSelectionMode(QAbstractItemView::ExtendedSelection);
  }

 protected:
  QStringList mimeTypes() const override { return {MainWindow::kChannelsMime}; }
  QMimeData* mimeData(const QList<QTreeWidgetItem*> items)
      const override {  // NOLINT(performance-unnecessary-value-param): Qt 5 signature
    QStringList lines;
    for (const QTreeWidgetItem* item : items) {
      if (item->parent() != nullptr) {
        lines << item->parent()->text(0) + "\t" + item->text(0);
      } else {
        for (int i = 0; i < item->childCount(); ++i) lines << item->text(0) + "\t" + item->child(i)->text(0);
      }
    }
    auto* data = new QMimeData;
    data->setData(MainWindow::kChannelsMime, lines.join("\n").toUtf8());
    return data;
  }
};

// Loads FILE; a MATLAB file without a mapping with the first known mapping that reads it.
std::unique_ptr<ViewInput> load_input(const std::string& file, const std::optional<std::string>& map) {
  const app::ViewInputOptions o;
  if (std::filesystem::path(file).extension() != ".mat" || map)
    return std::make_unique<ViewInput>(app::load_view_input(file, map, o));
  std::string errors;
  for (const auto& name : io::list_mappings(app::resource_subfolders("mappings"))) {
    try {
      auto in = std::make_unique<ViewInput>(app::load_view_input(file, name, o));
      in->notes.push_back("mapping " + name);
      return in;
    } catch (const std::exception& e) {
      errors = e.what();
    }
  }
  throw InputError(file, "no known mapping reads this MATLAB file (" + errors + ")");
}

std::vector<std::string> soil_names() {
  std::vector<std::string> names;
  for (const auto& folder : app::resource_subfolders("soils")) {
    for (const auto& e : std::filesystem::directory_iterator(folder)) {
      if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
    }
  }
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

MainWindow::MainWindow(QWidget* parent) : QMainWindow(parent), jobs_(std::make_unique<JobRunner>()) {
  setWindowTitle("RoverLab");
  setAcceptDrops(true);
  build_ui();
  QSettings settings;
  restoreGeometry(settings.value("window/geometry").toByteArray());
  const QByteArray state = settings.value("window/state").toByteArray();
  if (window_state_is_sound(state)) restoreState(state);  // a damaged settings file must not crash the GUI
  refresh_recent_menu();
}

MainWindow::~MainWindow() {
  jobs_->cancel();
  jobs_->wait();
  // The scenes own VTK objects the widgets render: drop them first.
  for (auto& tab : view_tabs_) tab.scene.reset();
}

MainWindow::ViewTab::ViewTab() = default;
MainWindow::ViewTab::ViewTab(ViewTab&&) noexcept = default;
MainWindow::ViewTab::~ViewTab() = default;

template <typename T>
T* MainWindow::scene_as() const {
  for (const auto& tab : view_tabs_) {
    if (auto* s = dynamic_cast<T*>(tab.scene.get())) return s;
  }
  return nullptr;
}

views::Scene* MainWindow::pane_scene(const QString& title) const {
  for (const auto& tab : view_tabs_) {
    if (tab.dock->windowTitle() == title) return tab.scene.get();
  }
  return nullptr;
}

views::RoverScene* MainWindow::rover_scene() const { return scene_as<views::RoverScene>(); }
views::TimeSeriesChart* MainWindow::chart() const { return scene_as<views::TimeSeriesChart>(); }
views::ContactAngleScene* MainWindow::contact_scene() const { return scene_as<views::ContactAngleScene>(); }

// The tab of the first view for which `uses` holds (nullptr when none).
MainWindow::ViewTab* MainWindow::tab_where(bool (views::View::*uses)() const) {
  for (auto& tab : view_tabs_) {
    if ((tab.view->*uses)()) return &tab;
  }
  return nullptr;
}

// No central widget: every view is a dock the user arranges (tabbed
// together at first, as the tabs were).
void MainWindow::build_ui() {
  resize(1400, 900);
  setDockNestingEnabled(true);
  setTabPosition(Qt::AllDockWidgetAreas, QTabWidget::North);
  build_menus();
  build_streams_dock();
  build_view_tabs();
  analysis_dock_ = new QDockWidget("Analysis");
  analysis_dock_->setObjectName("pane/analysis");
  analysis_dock_->setWidget(build_analysis_tab());
  addDockWidget(Qt::RightDockWidgetArea, analysis_dock_);
  if (!view_tabs_.empty()) {
    tabifyDockWidget(view_tabs_.front().dock, analysis_dock_);
    view_tabs_.front().dock->raise();
  }
  build_layout_menu();
  build_timeline();
  build_status_bar();
  // The streams a narrow column, the panes the rest.
  if (auto* streams = findChild<QDockWidget*>("streams"); streams != nullptr && !view_tabs_.empty()) {
    resizeDocks({streams, view_tabs_.front().dock}, {330, 1070}, Qt::Horizontal);
  }
}

void MainWindow::build_menus() {
  QMenu* file = menuBar()->addMenu("&File");
  QAction* open = file->addAction("&Open...");
  open->setShortcut(QKeySequence::Open);
  connect(open, &QAction::triggered, this, [this] {
    QSettings settings;
    const QString path =
        QFileDialog::getOpenFileName(this, "Open a rover log", settings.value("files/last_dir").toString(),
                                     "Rover logs (*.h5 *.hdf5 *.mat *.csv *.bag *.mcap);;All files (*)");
    if (!path.isEmpty()) open_file(path);
  });
  QAction* compare = file->addAction("&Compare with...");
  compare->setStatusTip("Open another run of the traverse and draw it against this log (Compare panes)");
  connect(compare, &QAction::triggered, this, [this] {
    if (!input_ || input_->is_wheel_test()) {
      show_error("Open a log first: another run is compared with it.");
      return;
    }
    QSettings settings;
    const QString path =
        QFileDialog::getOpenFileName(this, "Compare with another run", settings.value("files/last_dir").toString(),
                                     "Rover logs (*.h5 *.hdf5 *.mat *.csv *.bag *.mcap);;All files (*)");
    if (!path.isEmpty()) compare_with(path);
  });
  recent_menu_ = file->addMenu("Open &recent");
  file->addSeparator();
  QAction* quit = file->addAction("&Quit");
  quit->setShortcut(QKeySequence::Quit);
  connect(quit, &QAction::triggered, this, &QWidget::close);
  QMenu* analysis = menuBar()->addMenu("&Analysis");
  for (const auto& a : app::all_analyses()) {
    QAction* run = analysis->addAction("Run: " + q(a->identity().title));
    connect(run, &QAction::triggered, this, [this, name = a->name()] { run_analyses({name}, true); });
  }
  // An analysis's choice (the contact-angle model the views show: chosen by the
  // data, the first value, or by hand); the analysis runs again with it.
  for (const auto& a : app::all_analyses()) {
    const std::optional<app::AnalysisChoice>& c = a->identity().choice;
    if (!c) continue;
    QMenu* menu = analysis->addMenu(q(c->menu));
    auto* group = new QActionGroup(this);
    for (const std::string& v : c->values) {
      QAction* act = menu->addAction(v == c->values.front() ? q(v + " (chosen by the data)") : q(v).toUpper());
      act->setCheckable(true);
      act->setChecked(v == c->values.front());
      group->addAction(act);
      connect(act, &QAction::triggered, this, [this, name = a->name(), option = c->option, v] {
        choices_[name] = option + " " + v;
        if (input_ && input_->result(name) != nullptr) run_analyses({name}, true);
      });
    }
  }
}

void MainWindow::build_streams_dock() {
  tree_ = new StreamsTree;
  tree_->setHeaderLabels({"stream / channel", "unit", "samples", "rate (Hz)"});
  // Counts and rates always whole; a long name elided in its middle (its end tells streams apart),
  // whole in its tooltip.
  tree_->header()->setStretchLastSection(false);
  tree_->header()->setSectionResizeMode(0, QHeaderView::Stretch);
  for (int k = 1; k < 4; ++k) tree_->header()->setSectionResizeMode(k, QHeaderView::ResizeToContents);
  tree_->setTextElideMode(Qt::ElideMiddle);
  connect(tree_, &QTreeWidget::itemDoubleClicked, this, [this](QTreeWidgetItem* item, int) {
    if (item->parent() == nullptr) return;
    if (item->parent()->parent() != nullptr) {  // a compared run's channel: drawn against the log's in Compare
      ViewTab* compare = tab_where(&views::View::compares_runs);
      if (compare == nullptr) return;
      const std::size_t target = plot_target_;  // the log's channels still go to the plot pane
      add_plot_channels(*compare, {{item->parent()->text(0).toStdString(), item->text(0).toStdString()}});
      plot_target_ = target;
      show_pane(compare->page);
      return;
    }
    add_plot_channel(item->parent()->text(0), item->text(0));
    if (plot_target_ < view_tabs_.size()) show_pane(view_tabs_[plot_target_].page);
  });
  // The title stays short enough for the dock's width; how to use the tree
  // is its header's tooltip and the status bar's hint (issue 48).
  tree_->headerItem()->setToolTip(0, "Double-click a channel, or drag it onto the plots");
  tree_->setStatusTip("Double-click a channel, or drag it onto the plots");
  auto* dock = new QDockWidget("Streams");
  dock->setObjectName("streams");
  dock->setWidget(tree_);
  addDockWidget(Qt::LeftDockWidgetArea, dock);
}

// One pane per registered view, in registry order, tabbed together.
void MainWindow::build_view_tabs() {
  for (const auto& view : views::all_views()) {
    ViewTab& tab = add_pane(*view, q("pane/" + view->name()), q(view->title()));
    if (view_tabs_.size() > 1) tabifyDockWidget(view_tabs_.front().dock, tab.dock);
    if (view->uses_channels() && plot_target_ == 0) plot_target_ = view_tabs_.size() - 1;
  }
}

MainWindow::ViewTab& MainWindow::add_pane(const views::View& view, const QString& name, const QString& title) {
  ViewTab tab;
  tab.view = &view;
  tab.widget = new QVTKOpenGLNativeWidget;
  if (view.trackball_camera()) {
    tab.widget->interactor()->SetInteractorStyle(vtkSmartPointer<vtkInteractorStyleTrackballCamera>::New());
  } else if (view.top_down_camera()) {  // pan and zoom, never turned: north stays up
    tab.widget->interactor()->SetInteractorStyle(vtkSmartPointer<vtkInteractorStyleRubberBand2D>::New());
  }
  tab.why = new QLabel("Nothing to show yet: open a log (File > Open, or drop a file here).");
  tab.why->setWordWrap(true);
  tab.why->setAlignment(Qt::AlignCenter);
  tab.why->setMargin(24);
  tab.page = new QStackedWidget;
  tab.page->addWidget(view.uses_surface_data() ? build_surface_page(tab.widget) : tab.widget);
  tab.page->addWidget(tab.why);
  tab.page->setCurrentIndex(view.uses_surface_data() ? 0 : 1);
  if (view.uses_channels()) {  // a drop target for channels dragged from the streams tree
    for (QWidget* target :
         {static_cast<QWidget*>(tab.widget), static_cast<QWidget*>(tab.page), static_cast<QWidget*>(tab.why)}) {
      target->setAcceptDrops(true);
      target->installEventFilter(this);
    }
  }
  tab.dock = new QDockWidget(title);
  tab.dock->setObjectName(name);
  tab.dock->setWidget(tab.page);
  addDockWidget(Qt::RightDockWidgetArea, tab.dock);
  connect(tab.dock, &QDockWidget::visibilityChanged, this, [this, k = view_tabs_.size()] {
    view_tabs_[k].stale = true;
    render_views();
  });
  view_tabs_.push_back(std::move(tab));
  return view_tabs_.back();
}

// View > Save layout, Load layout: the panes' arrangement and the plotted channels, to reuse on another log.
void MainWindow::build_layout_menu() {
  QMenu* menu = menuBar()->addMenu("&View");
  view_menu_ = menu;
  for (const auto& tab : view_tabs_) menu->addAction(tab.dock->toggleViewAction());
  menu->addAction(analysis_dock_->toggleViewAction());
  menu->addSeparator();
  QAction* add_plots = menu->addAction("&New plot pane");
  add_plots->setShortcut(QKeySequence("Ctrl+Shift+P"));
  connect(add_plots, &QAction::triggered, this, [this] { new_plot_pane(); });
  connect(menu->addAction("&Fit plots to their data"), &QAction::triggered, this, &MainWindow::fit_plots);
  menu->addSeparator();
  connect(menu->addAction("&Save layout..."), &QAction::triggered, this, [this] {
    const QString path = QFileDialog::getSaveFileName(this, "Save the layout", {}, "RoverLab layouts (*.json)");
    if (path.isEmpty()) return;
    try {
      save_layout(path);
    } catch (const std::exception& e) {
      show_error(e.what());
    }
  });
  connect(menu->addAction("&Load layout..."), &QAction::triggered, this, [this] {
    const QString path = QFileDialog::getOpenFileName(this, "Apply a layout", {}, "RoverLab layouts (*.json)");
    if (path.isEmpty()) return;
    try {
      apply_layout(path);
    } catch (const std::exception& e) {
      show_error(e.what());
    }
  });
}

void MainWindow::show_pane(QWidget* page) {
  for (const auto& tab : view_tabs_) {
    if (tab.page != page) continue;
    tab.dock->show();
    tab.dock->raise();
  }
}

QDockWidget* MainWindow::pane(const QString& title) const {
  for (const auto& tab : view_tabs_) {
    if (tab.dock->windowTitle() == title) return tab.dock;
  }
  return analysis_dock_->windowTitle() == title ? analysis_dock_ : nullptr;
}

QString MainWindow::pane_note(const QString& title) const {
  for (const auto& tab : view_tabs_) {
    if (tab.dock->windowTitle() != title) continue;
    if (tab.page->currentWidget() == tab.why) return tab.why->text();
    const bool surface_why = tab.view->uses_surface_data() && surface_stack_->currentWidget() == surface_why_;
    return surface_why ? surface_why_->text() : QString();
  }
  return {};
}

// The traction surface's page: its soil and quantity above the view.
QWidget* MainWindow::build_surface_page(QVTKOpenGLNativeWidget* widget) {
  auto* page = new QWidget;
  auto* layout = new QVBoxLayout(page);
  auto* bar = new QHBoxLayout;
  surface_soil_ = new QComboBox;
  surface_soil_->addItem("(fit to the points)");
  for (const auto& s : soil_names()) surface_soil_->addItem(q(s));
  surface_quantity_ = new QComboBox;
  surface_quantity_->addItems({"drawbar-pull", "torque", "lateral-force"});  // F_y at the largest slip angle
  surface_note_ = new QLabel;
  surface_note_->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Preferred);
  bar->addWidget(new QLabel("model soil:"));
  bar->addWidget(surface_soil_);
  bar->addWidget(new QLabel("quantity:"));
  bar->addWidget(surface_quantity_);
  bar->addWidget(surface_note_, 1);
  layout->addLayout(bar);
  // Nothing to draw: the reason in words, whole, where the (else black) canvas would be.
  surface_why_ = new QLabel;
  surface_why_->setWordWrap(true);
  surface_why_->setAlignment(Qt::AlignCenter);
  surface_why_->setMargin(24);
  surface_stack_ = new QStackedWidget;
  surface_stack_->addWidget(widget);
  surface_stack_->addWidget(surface_why_);
  surface_why_->setText("Nothing to show yet: open a log or a single-wheel test (File > Open).");
  surface_stack_->setCurrentIndex(1);
  layout->addWidget(surface_stack_, 1);
  connect(surface_soil_, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this] { rebuild_surface(); });
  connect(surface_quantity_, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this] { rebuild_surface(); });
  return page;
}

void MainWindow::build_timeline() {
  auto* timeline = new QToolBar("Timeline");
  timeline->setObjectName("timeline");
  play_ = new QToolButton;
  play_->setText("Play");
  play_->setCheckable(true);
  speed_ = new QComboBox;
  speed_->addItems({"0.25x", "0.5x", "1x", "2x", "4x", "8x"});
  speed_->setCurrentIndex(2);
  slider_ = new QSlider(Qt::Horizontal);
  slider_->setRange(0, kSliderSteps);
  time_label_ = new QLabel("t = -");
  time_label_->setMinimumWidth(160);
  timeline->addWidget(play_);
  timeline->addWidget(speed_);
  timeline->addWidget(slider_);
  timeline->addWidget(time_label_);
  addToolBar(Qt::BottomToolBarArea, timeline);
  connect(slider_, &QSlider::valueChanged, this, [this](int v) {
    if (!input_) return;
    const double t = t0_ + (t1_ - t0_) * v / kSliderSteps;
    if (std::abs(t - time_) > 1e-9) set_time(t);
  });
  render_timer_ = new QTimer(this);
  render_timer_->setSingleShot(true);
  render_timer_->setInterval(16);
  connect(render_timer_, &QTimer::timeout, this, &MainWindow::render_next);
  player_ = new QTimer(this);
  player_->setInterval(33);
  connect(player_, &QTimer::timeout, this, &MainWindow::on_tick);
  connect(play_, &QToolButton::toggled, this, [this](bool on) {
    play_->setText(on ? "Pause" : "Play");
    last_tick_ms_ = QDateTime::currentMSecsSinceEpoch();
    if (on) {
      if (time_ >= t1_) set_time(t0_);
      player_->start();
    } else {
      player_->stop();
    }
  });
}

// The status bar with the job's progress and cancel.
void MainWindow::build_status_bar() {
  status_ = new QLabel("Open a log: File > Open, or drop a file here.");
  // A long line is cut at the window's edge, never widens the window past the screen.
  status_->setSizePolicy(QSizePolicy::Ignored, QSizePolicy::Preferred);
  status_->setMinimumWidth(40);
  progress_ = new QProgressBar;
  progress_->setRange(0, 1000);
  progress_->setMaximumWidth(240);
  progress_->setVisible(false);
  cancel_ = new QPushButton("Cancel");
  cancel_->setVisible(false);
  statusBar()->addWidget(status_, 1);
  statusBar()->addPermanentWidget(progress_);
  statusBar()->addPermanentWidget(cancel_);
  connect(cancel_, &QPushButton::clicked, this, [this] { jobs_->cancel(); });
  connect(jobs_.get(), &JobRunner::started, this, [this](const QString& title) {
    status_->setText(title + "...");
    progress_->setValue(0);
    progress_->setVisible(true);
    cancel_->setVisible(true);
  });
  connect(jobs_.get(), &JobRunner::progress, this,
          [this](double f) { progress_->setValue(static_cast<int>(1000.0 * std::clamp(f, 0.0, 1.0))); });
  connect(jobs_.get(), &JobRunner::finished, this, [this](const QString& title, const QString& error) {
    progress_->setVisible(false);
    cancel_->setVisible(false);
    if (error == "cancelled") {
      status_->setText(title + ": cancelled");
    } else if (!error.isEmpty()) {
      status_->setText(title + ": failed");
      show_error(error);
    } else {
      status_->setText(title + ": done");
    }
  });
}

// The Analysis tab: each analysis's result as the command line prints it, its
// result document as a tree, the slip-class confusion matrix and the
// odometry candidates.
QWidget* MainWindow::build_analysis_tab() {
  auto* page = new QWidget;
  auto* layout = new QVBoxLayout(page);
  analysis_text_ = new QLabel("Open a log to run the analyses that fit it (Analysis menu: run one by hand).");
  analysis_text_->setWordWrap(true);
  analysis_text_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  QFont mono("monospace");
  mono.setStyleHint(QFont::TypeWriter);
  analysis_text_->setFont(mono);
  results_ = new QTreeWidget;
  results_->setHeaderLabels({"result", "value"});
  results_->header()->setSectionResizeMode(0, QHeaderView::ResizeToContents);
  tables_ = new QWidget;  // each table whole, in a scroll area of their own
  tables_->setLayout(new QVBoxLayout);
  tables_->layout()->setContentsMargins(0, 0, 0, 0);
  auto* tables_scroll = new QScrollArea;
  tables_scroll->setWidget(tables_);
  tables_scroll->setWidgetResizable(true);
  auto* scroll = new QScrollArea;
  scroll->setWidget(analysis_text_);
  scroll->setWidgetResizable(true);
  layout->addWidget(scroll, 1);
  layout->addWidget(results_, 1);
  layout->addWidget(tables_scroll, 2);
  return page;
}

void MainWindow::show_error(const QString& text) {
  last_error_ = text;
  if (!quiet_) QMessageBox::critical(this, "RoverLab", text);
}

void MainWindow::open_file(const QString& path, const std::optional<QString>& mapping) {
  if (jobs_->busy()) {
    show_error("A job is running (" + jobs_->title() + "): wait for it or cancel it first.");
    return;
  }
  const std::string file = path.toStdString();
  std::optional<std::string> map;
  if (mapping) map = mapping->toStdString();
  jobs_->start("loading " + QFileInfo(path).fileName(),
               [this, file, map, path](const JobControl& c) -> std::function<void()> {
                 std::unique_ptr<ViewInput> in = load_input(file, map);
                 // Results stored with the log (estimate X -o) are shown, not computed again.
                 for (auto& an : app::all_analyses()) app::reuse_stored_result(*in, std::move(an));
                 c.check();
                 auto shared = std::make_shared<std::unique_ptr<ViewInput>>(std::move(in));
                 return [this, shared, path] {
                   install(std::move(*shared));
                   if (keeps_settings_) {
                     remember_recent(path);
                     QSettings().setValue("files/last_dir", QFileInfo(path).absolutePath());
                   }
                   setWindowTitle("RoverLab - " + QFileInfo(path).fileName());
                   emit log_loaded();
                   // Estimates arrive as new streams from the analyses that fit the log.
                   std::vector<std::string> names;
                   for (const auto& an : app::all_analyses()) {
                     if (input_->result(an->name()) == nullptr && an->runs_on_open(input_->log))
                       names.push_back(an->name());
                   }
                   if (!names.empty()) {
                     estimator_pending_ = true;
                     QTimer::singleShot(0, this, [this, names] {
                       estimator_pending_ = false;
                       run_analyses(names, false);
                     });
                   }
                 };
               });
}

void MainWindow::compare_with(const QString& path, const std::optional<QString>& mapping) {
  if (jobs_->busy()) {
    show_error("A job is running (" + jobs_->title() + "): wait for it or cancel it first.");
    return;
  }
  if (!input_ || input_->is_wheel_test()) {
    show_error("Open a log first: another run is compared with it.");
    return;
  }
  const std::string file = path.toStdString();
  std::optional<std::string> map;
  if (mapping) map = mapping->toStdString();
  jobs_->start("loading " + QFileInfo(path).fileName() + " to compare",
               [this, file, map](const JobControl& c) -> std::function<void()> {
                 auto shared = std::make_shared<std::unique_ptr<ViewInput>>(load_input(file, map));
                 c.check();
                 if ((*shared)->is_wheel_test()) throw InputError(file, "single-wheel test points are not a run");
                 return [this, shared, file] {
                   compared_.push_back({std::filesystem::path(file).stem().string(), std::move(*shared)});
                   const double t = time_;
                   rebuild_tree();
                   QWidget* shown = nullptr;
                   for (auto& tab : view_tabs_) {
                     if (tab.view->compares_runs() && rebuild_view(tab) && shown == nullptr) shown = tab.page;
                     if (tab.view->compares_runs()) tab.stale = true;
                   }
                   if (shown != nullptr) show_pane(shown);
                   status_->setText(q("Comparing " + input_->file + " (baseline) with " + file + "."));
                   set_time(t);
                 };
               });
}

void MainWindow::run_analyses(const std::vector<std::string>& names, bool by_hand) {
  if (!input_ || input_->is_wheel_test()) return;
  const log::Log* lg = &input_->log;
  std::vector<std::shared_ptr<app::Analysis>> todo;
  for (const auto& name : names) {
    std::shared_ptr<app::Analysis> a = app::make_analysis(name);
    const std::string missing = a->missing(*lg);
    if (!missing.empty()) {
      if (by_hand) show_error(q(a->identity().title + " cannot run on this log: " + missing + "."));
      continue;
    }
    if (const auto chosen = choices_.find(a->name()); chosen != choices_.end()) {  // chosen in the Analysis menu
      CLI::App options;
      a->declare(options);
      options.parse(chosen->second, false);
    }
    todo.push_back(std::move(a));
  }
  if (todo.empty()) return;
  const QString title = todo.size() == 1 ? q(todo.front()->identity().title) : QString("%1 analyses").arg(todo.size());
  const std::string file = input_->file;
  jobs_->start(title, [this, lg, todo, file](const JobControl& c) -> std::function<void()> {
    auto results = std::make_shared<std::vector<app::AnalysisResult>>();
    const auto n = static_cast<double>(todo.size());
    for (std::size_t k = 0; k < todo.size(); ++k) {
      const auto progress = [&c, k, n](double f) {
        c.report((static_cast<double>(k) + f) / n);
        c.check();
      };
      results->push_back(app::run_analysis(*todo[k], {*lg, file, progress}));
      c.check();
    }
    return [this, todo, results] {
      for (std::size_t k = 0; k < todo.size(); ++k) input_->add(todo[k], std::move((*results)[k]));
      const double t = time_;
      rebuild_tree();
      QWidget* shown = rebuild_views();  // a view the new estimates made available comes to the front
      rebuild_analysis();
      rebuild_surface();  // a rover's net-traction estimates feed the traction-surface tab
      if (shown != nullptr) show_pane(shown);
      set_time(t);
    };
  });
}

void MainWindow::install(std::unique_ptr<ViewInput> in) {
  play_->setChecked(false);
  for (auto& tab : view_tabs_) {
    tab.available = false;
    if (!tab.scene || tab.view->resets_scene()) continue;  // a scene reset in place lives as long as its widget
    tab.scene->detach(tab.widget->renderWindow());
    tab.scene.reset();
  }
  input_ = std::move(in);
  compared_.clear();  // runs compared with the log before
  const QString missing = plot_layout_channels();
  rebuild_tree();
  rebuild_views();
  rebuild_analysis();
  rebuild_surface();
  QString notes;
  for (const auto& n : input_->notes) notes += q(n) + "; ";
  status_->setText(QString("%1 loaded. %2%3").arg(q(input_->file), missing, notes));
  if (const ViewTab* surface = tab_where(&views::View::uses_surface_data); surface && input_->is_wheel_test()) {
    show_pane(surface->page);
  }
  set_time(t0_);
}

void MainWindow::rebuild_tree() {
  tree_->clear();
  if (!input_) return;
  if (input_->is_wheel_test()) {
    auto* item =
        new QTreeWidgetItem(tree_, {"single-wheel points", "", QString::number(input_->wheel_points.size()), ""});
    item->setExpanded(true);
    return;
  }
  for (const auto& s : input_->log.streams()) {
    auto* item = new QTreeWidgetItem(
        tree_, {q(s.name()), "", QString::number(s.size()), QString::number(s.mean_rate_hz(), 'f', 1)});
    item->setToolTip(0, q(s.name()));
    item->setToolTip(2, QString("%1 samples").arg(s.size()));
    for (const auto& c : s.channels()) {
      auto* channel = new QTreeWidgetItem(item, {q(c.name), q(c.unit), "", ""});
      channel->setToolTip(0, q(s.name() + ":" + c.name));
    }
  }
  // Each compared run under its own name: its channels go to the Compare pane (double-click), not dragged.
  for (const auto& run : compared_) {
    auto* top = new QTreeWidgetItem(tree_, {q(run.name + " (compared)"), "", "", ""});
    top->setToolTip(0, q(run.input->file + ": compared with the log (File > Compare with...)"));
    top->setFlags(top->flags() & ~Qt::ItemIsDragEnabled);
    for (const auto& s : run.input->log.streams()) {
      auto* item = new QTreeWidgetItem(
          top, {q(s.name()), "", QString::number(s.size()), QString::number(s.mean_rate_hz(), 'f', 1)});
      item->setFlags(item->flags() & ~Qt::ItemIsDragEnabled);
      for (const auto& c : s.channels()) {
        auto* channel = new QTreeWidgetItem(item, {q(c.name), q(c.unit), "", ""});
        channel->setFlags(channel->flags() & ~Qt::ItemIsDragEnabled);
        channel->setToolTip(0, q(run.name + ": " + s.name() + ":" + c.name + " (double-click: compare it)"));
      }
    }
  }
}

QWidget* MainWindow::rebuild_views() {
  if (!input_ || input_->is_wheel_test()) {
    for (auto& tab : view_tabs_) {
      if (tab.view->uses_surface_data()) continue;
      if (input_ && tab.view->uses_lab_figures()) {  // a single-wheel file's own views
        rebuild_view(tab);
        continue;
      }
      tab.why->setText(q("Nothing to show: " + (input_ ? input_->file : std::string("no log")) +
                         " is a single-wheel test table, drawn in the Traction surface pane."));
      tab.page->setCurrentWidget(tab.why);
    }
    t0_ = 0;
    t1_ = 1;
    return nullptr;
  }
  QWidget* shown = nullptr;
  for (auto& tab : view_tabs_) {
    if (tab.view->uses_surface_data()) continue;  // rebuild_surface: its own soil and quantity
    if (rebuild_view(tab) && shown == nullptr) shown = tab.page;
  }
  // Timeline over every stream.
  const log::Log& lg = input_->log;
  bool first = true;
  for (const auto& s : lg.streams()) {
    if (s.empty()) continue;
    t0_ = first ? s.start_time() : std::min(t0_, s.start_time());
    t1_ = first ? s.end_time() : std::max(t1_, s.end_time());
    first = false;
  }
  if (!(t1_ > t0_)) t1_ = t0_ + 1.0;
  return shown;
}

// Builds the tab's scene from the log (the planar side view for rocker-bogie
// simulations, plots of the chosen channels, ...), or resets it in place;
// true when the view was not available before. A view the log cannot feed
// keeps no scene, but one its view resets in place stays for the widget's
// lifetime.
bool MainWindow::rebuild_view(ViewTab& tab) {
  const log::Log& lg = input_->log;
  views::SceneInput in;
  in.log = &lg;
  in.rover = app::rover_geometry(lg);
  in.articulated = app::rover_kinematics(lg);
  if (tab.view->compares_runs()) {  // the channels picked for it, else its own choice
    for (const auto& [s, c] : tab.channels) in.channels.push_back({s, c});
    for (const auto& run : compared_) in.compared.emplace_back(run.name, &run.input->log);
  } else if (tab.view->uses_channels()) {
    plot_input(tab, in);
  }
  if (tab.view->uses_lab_figures()) in.lab = app::lab_figures_of(*input_, std::nullopt);  // the file's baseline
  vtkRenderWindow* window = tab.widget->renderWindow();
  const bool was = tab.available;
  const std::string title = tab.dock->windowTitle().toStdString();
  // A plot pane the user added plots what is dropped on it, nothing before.
  std::string missing = tab.added && in.channels.empty() ? empty_plot_note(tab) : tab.view->needs(in);
  std::unique_ptr<views::Scene> compared;  // runs that cannot be aligned, or a channel one run lacks: said in the pane
  if (missing.empty() && tab.view->compares_runs()) {
    try {
      compared = tab.view->build(in);
    } catch (const DataError& e) {
      missing = e.what();
    }
  }
  tab.available = missing.empty();
  // A view the log cannot feed says why, in words, where its picture would be.
  tab.why->setText(q("Nothing to show in " + title + ": " + missing));
  if (!tab.view->uses_surface_data()) tab.page->setCurrentIndex(tab.available ? 0 : 1);
  if (!tab.available) {
    if (tab.scene && !tab.view->resets_scene()) {
      tab.scene->detach(window);
      tab.scene.reset();
    }
    return false;
  }
  if (!tab.scene || !tab.view->reset(*tab.scene, in)) {
    if (tab.scene) tab.scene->detach(window);
    tab.scene = compared ? std::move(compared) : tab.view->build(in);
    tab.scene->attach(window);
  }
  if (auto* plots = dynamic_cast<views::TimeSeriesChart*>(tab.scene.get())) {  // zoom linked across plot panes
    plots->on_user_window([this, k = static_cast<std::size_t>(&tab - view_tabs_.data())](double t0, double t1) {
      follow_window(k, t0, t1);
    });
  }
  tab.scene->fit_width(std::max(400, tab.widget->width()));
  return !was;
}

namespace {

// A JSON value as a tree item's text: numbers to 4 significant digits, short
// arrays of numbers on one line.
QString json_text(const nlohmann::json& v) {
  if (v.is_number_float()) return QString::number(v.get<double>(), 'g', 4);
  if (v.is_null()) return "-";
  if (v.is_string()) return q(v.get<std::string>());
  if (v.is_array() && !v.empty() && v.size() <= 8 &&
      std::all_of(v.begin(), v.end(), [](const nlohmann::json& e) { return e.is_primitive(); })) {
    QStringList cells;
    for (const auto& e : v) cells << json_text(e);
    return cells.join(", ");
  }
  if (v.is_structured()) return {};
  return q(v.dump());
}

void add_json_items(QTreeWidgetItem* parent, const nlohmann::json& v) {
  for (auto it = v.begin(); it != v.end(); ++it) {
    const QString key = v.is_object() ? q(it.key()) : QString("[%1]").arg(parent->childCount());
    auto* item = new QTreeWidgetItem(parent, {key, json_text(*it)});
    if (it->is_structured() && item->text(1).isEmpty()) add_json_items(item, *it);
  }
}

// One table of a result (Presentation::tables) as a table widget named by its title.
QWidget* table_widget(const app::ResultTable& t) {
  auto* table = new QTableWidget(static_cast<int>(t.rows.size()), static_cast<int>(t.columns.size()));
  table->setObjectName(q(t.title));
  QStringList columns, rows;
  for (const auto& c : t.columns) columns << q(c);
  for (const auto& r : t.row_names) rows << q(r);
  table->setHorizontalHeaderLabels(columns);
  if (!rows.isEmpty()) table->setVerticalHeaderLabels(rows);
  table->verticalHeader()->setVisible(!rows.isEmpty());
  table->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  table->setEditTriggers(QAbstractItemView::NoEditTriggers);
  for (std::size_t i = 0; i < t.rows.size(); ++i) {
    for (std::size_t k = 0; k < t.rows[i].size() && k < t.columns.size(); ++k) {
      const app::ResultTable::Cell& cell = t.rows[i][k];
      auto* item = new QTableWidgetItem(q(cell.text));
      if (cell.shade > 0.0) {
        const double f = 1.0 - 0.5 * std::min(1.0, cell.shade);
        item->setBackground(QColor::fromRgbF(f, f, 1.0));
      }
      if (cell.bold) {
        QFont font = item->font();
        font.setBold(true);
        item->setFont(font);
      }
      table->setItem(static_cast<int>(i), static_cast<int>(k), item);
    }
  }
  // Tall enough for every row: the scroll area around the tables scrolls, not each table.
  table->resizeRowsToContents();
  int height = table->horizontalHeader()->sizeHint().height() + 2 * table->frameWidth();
  for (int i = 0; i < table->rowCount(); ++i) height += table->rowHeight(i);
  if (table->horizontalScrollBarPolicy() != Qt::ScrollBarAlwaysOff)
    height += table->horizontalScrollBar()->sizeHint().height();
  table->setFixedHeight(height);
  table->setVerticalScrollBarPolicy(Qt::ScrollBarAlwaysOff);
  return table;
}

}  // namespace

void MainWindow::rebuild_analysis() {
  while (QLayoutItem* old = tables_->layout()->takeAt(0)) {
    delete old->widget();
    delete old;
  }
  results_->clear();
  if (!input_) return;
  QString text;
  for (const auto& run : input_->analyses) {
    text += "<b>" + q(run.title).toHtmlEscaped() + "</b><pre>" +
            q(app::printed(*run.analysis, run.document)).toHtmlEscaped() + "</pre>";
    auto* top = new QTreeWidgetItem(results_, {q(run.title), ""});
    add_json_items(top, run.document);
    for (const app::ResultTable& t : run.analysis->presentation().tables(run.document)) {
      tables_->layout()->addWidget(new QLabel(q(t.title)));
      tables_->layout()->addWidget(table_widget(t));
      if (!t.legend.empty()) {  // what bold, the tint and the order mean, under the table
        auto* legend = new QLabel(q(t.legend));
        legend->setObjectName(q(t.title + " (legend)"));
        legend->setWordWrap(true);
        tables_->layout()->addWidget(legend);
      }
    }
  }
  static_cast<QVBoxLayout*>(tables_->layout())->addStretch(1);
  if (text.isEmpty()) text = "No analyses yet: none of the registered analyses can run on this log.";
  analysis_text_->setText(text);
}

void MainWindow::rebuild_surface() {
  ViewTab* tab = tab_where(&views::View::uses_surface_data);
  if (!input_ || tab == nullptr) return;
  vtkRenderWindow* window = tab->widget->renderWindow();
  if (tab->scene) tab->scene->detach(window);
  tab->scene.reset();
  app::ViewOptions o;
  if (surface_soil_->currentIndex() > 0) o.soil = surface_soil_->currentText().toStdString();
  o.quantity = surface_quantity_->currentText().toStdString();
  try {
    const views::SceneInput in = app::scene_input(*input_, *tab->view, o);
    tab->scene = tab->view->build(in);
    tab->scene->attach(window);
    surface_note_->setText(QString("%1: %2 points").arg(q(in.surface->quantity)).arg(in.surface->points.size()));
    surface_note_->setToolTip(surface_note_->text());
    surface_stack_->setCurrentIndex(0);
  } catch (const std::exception& e) {
    surface_note_->setText("nothing to draw");
    surface_note_->setToolTip(e.what());
    surface_why_->setText(QString("Nothing to draw in %1: %2").arg(tab->dock->windowTitle(), e.what()));
    surface_stack_->setCurrentIndex(1);
  }
  window->Render();
}

void MainWindow::set_time(double t) {
  time_ = std::clamp(t, t0_, t1_);
  {
    const QSignalBlocker block(slider_);
    slider_->setValue(static_cast<int>(std::lround((time_ - t0_) / (t1_ - t0_) * kSliderSteps)));
  }
  time_label_->setText(QString("t = %1 s / %2 s").arg(time_, 0, 'f', 2).arg(t1_, 0, 'f', 1));
  for (auto& tab : view_tabs_) {
    if (!tab.scene) continue;
    tab.scene->set_time(time_);
    tab.stale = true;
  }
  render_views();
  emit time_changed(time_);
}

void MainWindow::render_views() {
  // Coalesced: however fast the timeline moves, the visible view renders at
  // most about 60 times a second, and hidden views not at all.
  if (!render_timer_->isActive()) render_timer_->start();
}

// The panes in view (side by side, or in front of their tab group: Qt keeps
// the others "visible" but off screen, so what counts is the region shown);
// the surface does not follow the timeline: its widget repaints itself.
bool MainWindow::renders(const ViewTab& tab) {
  return tab.widget->isVisible() && !tab.widget->visibleRegion().isEmpty() && tab.scene && tab.scene->follows_time();
}

void MainWindow::render_pane(ViewTab& tab) {
  // A pane the user resized (moved beside another, floated) is laid out again for its size.
  if (tab.widget->width() != tab.fitted_width || tab.widget->height() != tab.fitted_height) {
    tab.fitted_width = tab.widget->width();
    tab.fitted_height = tab.widget->height();
    tab.scene->fit_width(std::max(400, tab.fitted_width));
  }
  tab.widget->renderWindow()->Render();
  tab.stale = false;
}

void MainWindow::render_now() {
  for (auto& tab : view_tabs_) {
    if (renders(tab)) render_pane(tab);
  }
}

// One pane a turn of the event loop: several panes side by side never hold
// it for more than one frame.
void MainWindow::render_next() {
  bool more = false;
  for (auto& tab : view_tabs_) {
    if (!tab.stale || !renders(tab)) continue;
    if (more) {
      QTimer::singleShot(0, this, &MainWindow::render_next);
      return;
    }
    render_pane(tab);
    more = true;
  }
}

bool MainWindow::select_tab(const QString& name) {
  QDockWidget* dock = pane(name);
  if (dock == nullptr) return false;
  dock->show();
  dock->raise();
  return true;
}

QStringList MainWindow::tab_names() const {
  QStringList names;
  for (const auto& tab : view_tabs_) names << tab.dock->windowTitle();
  names << analysis_dock_->windowTitle();
  return names;
}

void MainWindow::on_tick() {
  const qint64 now = QDateTime::currentMSecsSinceEpoch();
  const double speeds[] = {0.25, 0.5, 1, 2, 4, 8};
  const double dt = 1e-3 * static_cast<double>(now - last_tick_ms_) * speeds[std::clamp(speed_->currentIndex(), 0, 5)];
  last_tick_ms_ = now;
  if (time_ + dt >= t1_) {
    set_time(t1_);
    play_->setChecked(false);
    return;
  }
  set_time(time_ + dt);
}

void MainWindow::remember_recent(const QString& path) {
  QSettings settings;
  QStringList recent = settings.value("files/recent").toStringList();
  recent.removeAll(QFileInfo(path).absoluteFilePath());
  recent.prepend(QFileInfo(path).absoluteFilePath());
  while (recent.size() > 10) recent.removeLast();
  settings.setValue("files/recent", recent);
  refresh_recent_menu();
}

void MainWindow::refresh_recent_menu() {
  recent_menu_->clear();
  const QStringList recent = QSettings().value("files/recent").toStringList();
  for (const QString& path : recent) {
    QAction* a = recent_menu_->addAction(path);
    connect(a, &QAction::triggered, this, [this, path] { open_file(path); });
  }
  recent_menu_->setEnabled(!recent.isEmpty());
}

void MainWindow::closeEvent(QCloseEvent* event) {
  // A running job is cancelled and waited for; its result is dropped.
  jobs_->cancel();
  jobs_->wait();
  if (keeps_settings_) {
    QSettings settings;
    settings.setValue("window/geometry", saveGeometry());
    settings.setValue("window/state", saveState());
  }
  event->accept();
}

void MainWindow::dragEnterEvent(QDragEnterEvent* event) {
  if (event->mimeData()->hasUrls()) event->acceptProposedAction();
}

void MainWindow::dropEvent(QDropEvent* event) {
  const auto urls = event->mimeData()->urls();
  if (!urls.isEmpty() && urls.front().isLocalFile()) open_file(urls.front().toLocalFile());
}

}  // namespace roverlab::gui
