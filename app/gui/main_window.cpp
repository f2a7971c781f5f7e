#include "app/gui/main_window.h"

#include <QAction>
#include <QApplication>
#include <QCloseEvent>
#include <QComboBox>
#include <QDateTime>
#include <QDockWidget>
#include <QDragEnterEvent>
#include <QDropEvent>
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
#include <QSettings>
#include <QSlider>
#include <QStatusBar>
#include <QTabWidget>
#include <QTableWidget>
#include <QTimer>
#include <QToolBar>
#include <QToolButton>
#include <QTreeWidget>
#include <QVBoxLayout>
#include <QVTKOpenGLNativeWidget.h>
#include <vtkContextView.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>
#include <vtkInteractorStyleTrackballCamera.h>
#include <vtkRenderWindowInteractor.h>

#include <cmath>
#include <filesystem>

#include "app/resources.h"
#include "core/common/error.h"
#include "core/estimation/slip.h"
#include "importers/mapping.h"
#include "importers/rover_file.h"
#include "views/contact_angle_scene.h"
#include "views/planar_rover_scene.h"
#include "views/rover_scene.h"
#include "views/timeseries_chart.h"
#include "views/traction_surface_scene.h"

namespace roverlab::gui {

namespace {

constexpr int kSliderSteps = 10000;

QString q(const std::string& s) { return QString::fromStdString(s); }

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
  restoreState(settings.value("window/state").toByteArray());
  refresh_recent_menu();
}

MainWindow::~MainWindow() {
  jobs_->cancel();
  jobs_->wait();
  // The scenes own VTK objects the widgets render: drop them first.
  rover_.reset();
  planar_.reset();
  contact_.reset();
}

void MainWindow::build_ui() {
  resize(1400, 900);
  // Menus.
  QMenu* file = menuBar()->addMenu("&File");
  QAction* open = file->addAction("&Open...");
  open->setShortcut(QKeySequence::Open);
  connect(open, &QAction::triggered, this, [this] {
    QSettings settings;
    const QString path = QFileDialog::getOpenFileName(
        this, "Open a rover log", settings.value("files/last_dir").toString(),
        "Rover logs (*.h5 *.hdf5 *.mat *.csv);;All files (*)");
    if (!path.isEmpty()) open_file(path);
  });
  recent_menu_ = file->addMenu("Open &recent");
  file->addSeparator();
  QAction* quit = file->addAction("&Quit");
  quit->setShortcut(QKeySequence::Quit);
  connect(quit, &QAction::triggered, this, &QWidget::close);
  QMenu* analysis = menuBar()->addMenu("&Analysis");
  QAction* ins = analysis->addAction("Run the INS slip estimator (seed 002)");
  connect(ins, &QAction::triggered, this, &MainWindow::run_estimator);
  QAction* contact = analysis->addAction("Run the contact-angle estimator (seed 000)");
  connect(contact, &QAction::triggered, this, &MainWindow::run_contact_estimator);
  QAction* odo = analysis->addAction("Study the wheel odometry against GPS");
  connect(odo, &QAction::triggered, this, [this] {
    if (!input_) return;
    const log::Log* lg = &input_->log;
    jobs_->start("odometry study", [this, lg](const JobControl& c) -> std::function<void()> {
      auto report = std::make_shared<analysis::OdometryDiscrepancyReport>(analysis::study_odometry(*lg));
      c.check();
      return [this, report] {
        input_->odometry = *report;
        rebuild_analysis();
        select_tab("Analysis");
      };
    });
  });

  // Streams dock.
  tree_ = new QTreeWidget;
  tree_->setHeaderLabels({"stream / channel", "unit", "samples", "rate (Hz)"});
  tree_->header()->setSectionResizeMode(0, QHeaderView::ResizeToContents);
  connect(tree_, &QTreeWidget::itemDoubleClicked, this, [this](QTreeWidgetItem* item, int) {
    if (item->parent() == nullptr) return;
    add_plot_channel(item->parent()->text(0), item->text(0));
    select_tab("Plots");
  });
  auto* dock = new QDockWidget("Streams (double-click a channel to plot it)");
  dock->setObjectName("streams");
  dock->setWidget(tree_);
  addDockWidget(Qt::LeftDockWidgetArea, dock);

  // Views.
  tabs_ = new QTabWidget;
  rover_widget_ = new QVTKOpenGLNativeWidget;
  plot_widget_ = new QVTKOpenGLNativeWidget;
  surface_widget_ = new QVTKOpenGLNativeWidget;
  rover_widget_->interactor()->SetInteractorStyle(vtkSmartPointer<vtkInteractorStyleTrackballCamera>::New());
  tabs_->addTab(rover_widget_, "Rover");
  tabs_->addTab(plot_widget_, "Plots");
  contact_widget_ = new QVTKOpenGLNativeWidget;
  tabs_->addTab(contact_widget_, "Contact angles");
  auto* surface_page = new QWidget;
  auto* surface_layout = new QVBoxLayout(surface_page);
  auto* surface_bar = new QHBoxLayout;
  surface_soil_ = new QComboBox;
  surface_soil_->addItem("(fit to the points)");
  for (const auto& s : soil_names()) surface_soil_->addItem(q(s));
  surface_quantity_ = new QComboBox;
  surface_quantity_->addItems({"drawbar-pull", "torque"});
  surface_note_ = new QLabel;
  surface_bar->addWidget(new QLabel("model soil:"));
  surface_bar->addWidget(surface_soil_);
  surface_bar->addWidget(new QLabel("quantity:"));
  surface_bar->addWidget(surface_quantity_);
  surface_bar->addWidget(surface_note_, 1);
  surface_layout->addLayout(surface_bar);
  surface_layout->addWidget(surface_widget_, 1);
  connect(surface_soil_, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this] { rebuild_surface(); });
  connect(surface_quantity_, QOverload<int>::of(&QComboBox::currentIndexChanged), this, [this] { rebuild_surface(); });
  tabs_->addTab(surface_page, "Traction surface");
  auto* analysis_page = new QWidget;
  auto* analysis_layout = new QVBoxLayout(analysis_page);
  analysis_text_ = new QLabel("Open a log with imu, wheels and gps streams to see the INS and odometry analyses.");
  analysis_text_->setWordWrap(true);
  analysis_text_->setTextInteractionFlags(Qt::TextSelectableByMouse);
  confusion_ = new QTableWidget(estimation::kSlipClasses, estimation::kSlipClasses);
  QStringList classes;
  for (int k = 0; k < estimation::kSlipClasses; ++k) classes << estimation::to_string(static_cast<estimation::SlipClass>(k));
  confusion_->setHorizontalHeaderLabels(classes);
  confusion_->setVerticalHeaderLabels(classes);
  confusion_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  confusion_->setMaximumHeight(200);
  candidates_ = new QTableWidget(0, 5);
  candidates_->setHorizontalHeaderLabels({"candidate", "fitted", "fit RMSE (m)", "held-out RMSE (m)", "held-out final (m)"});
  candidates_->horizontalHeader()->setSectionResizeMode(QHeaderView::ResizeToContents);
  candidates_->setEditTriggers(QAbstractItemView::NoEditTriggers);
  analysis_layout->addWidget(analysis_text_);
  analysis_layout->addWidget(new QLabel("Slip classes, column-normalised (rows: estimated, columns: reference)"));
  analysis_layout->addWidget(confusion_);
  analysis_layout->addWidget(new QLabel("What the wheel odometry gets wrong: candidate causes"));
  analysis_layout->addWidget(candidates_, 1);
  tabs_->addTab(analysis_page, "Analysis");

  // Timeline.
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
  connect(render_timer_, &QTimer::timeout, this, &MainWindow::render_now);
  connect(tabs_, &QTabWidget::currentChanged, this, [this] { render_views(); });
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

  setCentralWidget(tabs_);

  // Status bar with the job's progress and cancel.
  status_ = new QLabel("Open a log: File > Open, or drop a file here.");
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
  jobs_->start("loading " + QFileInfo(path).fileName(), [this, file, map, path](const JobControl& c) -> std::function<void()> {
    app::ViewInputOptions o;
    o.run_estimator = false;
    std::unique_ptr<ViewInput> in;
    const bool mat = std::filesystem::path(file).extension() == ".mat";
    if (mat && !map) {
      // A MATLAB file needs a mapping: the first known one that reads it.
      std::string errors;
      for (const auto& name : io::list_mappings(app::resource_subfolders("mappings"))) {
        try {
          in = std::make_unique<ViewInput>(app::load_view_input(file, name, o));
          in->notes.push_back("mapping " + name);
          break;
        } catch (const std::exception& e) {
          errors = e.what();
        }
      }
      if (!in) throw InputError(file, "no known mapping reads this MATLAB file (" + errors + ")");
    } else {
      in = std::make_unique<ViewInput>(app::load_view_input(file, map, o));
    }
    c.check();
    auto shared = std::make_shared<std::unique_ptr<ViewInput>>(std::move(in));
    return [this, shared, path] {
      install(std::move(*shared));
      remember_recent(path);
      QSettings().setValue("files/last_dir", QFileInfo(path).absolutePath());
      setWindowTitle("RoverLab - " + QFileInfo(path).fileName());
      emit log_loaded();
      // Estimates arrive as new streams when the log can be estimated.
      const log::Log& lg = input_->log;
      if (lg.find_stream("joints") && lg.find_stream("imu") && lg.find_stream("wheels") &&
          !lg.find_stream("estimate/contact/wheels")) {
        estimator_pending_ = true;
        QTimer::singleShot(0, this, [this] {
          estimator_pending_ = false;
          run_contact_estimator();
        });
      } else if (lg.find_stream("imu") && lg.find_stream("wheels") && lg.stream("wheels").find_channel("angle_FL") &&
                 !lg.find_stream("estimate/ins/pose")) {
        estimator_pending_ = true;
        QTimer::singleShot(0, this, [this] {
          estimator_pending_ = false;
          run_estimator();
        });
      }
    };
  });
}

void MainWindow::run_estimator() {
  if (!input_ || input_->is_wheel_test()) return;
  const log::Log* lg = &input_->log;
  if (!lg->find_stream("imu") || !lg->find_stream("wheels")) {
    show_error("The INS slip estimator needs imu and wheels streams; this log has "
               + QString(lg->find_stream("imu") ? "no wheels." : "no imu."));
    return;
  }
  jobs_->start("INS slip estimator", [this, lg](const JobControl& c) -> std::function<void()> {
    estimation::InsSlipOptions o;
    o.progress = [&c](double f) {
      c.report(0.9 * f);
      c.check();
    };
    auto result = std::make_shared<estimation::InsSlipResult>(estimation::run_ins_slip(*lg, o));
    c.report(0.9);
    std::shared_ptr<analysis::OdometryDiscrepancyReport> odo;
    if (lg->find_stream("gps")) {
      try {
        odo = std::make_shared<analysis::OdometryDiscrepancyReport>(analysis::study_odometry(*lg));
      } catch (const DataError&) {
      }
    }
    c.check();
    return [this, result, odo] {
      for (const auto& s : result->estimates.streams()) {
        if (input_->log.find_stream(s.name()) == nullptr) input_->log.add_stream(s);
      }
      input_->ins = *result;
      if (odo) input_->odometry = *odo;
      const double t = time_;
      rebuild_tree();
      rebuild_views();
      rebuild_analysis();
      set_time(t);
    };
  });
}

void MainWindow::run_contact_estimator() {
  if (!input_ || input_->is_wheel_test()) return;
  const log::Log* lg = &input_->log;
  if (!lg->find_stream("joints") || !lg->find_stream("imu") || !lg->find_stream("wheels")) {
    show_error("The contact-angle estimator needs imu, joints and wheels streams of a six-wheel DH rover.");
    return;
  }
  const std::string rover_name = app::rover_name_of(*lg);
  jobs_->start("contact-angle estimator", [this, lg, rover_name](const JobControl& c) -> std::function<void()> {
    const io::RoverDescription d = io::find_rover(rover_name, app::resource_subfolders("rovers"));
    if (!d.dh) throw InputError(d.file, "rover " + d.name + " has no DH description");
    estimation::ContactAngleOptions o = app::view_contact_options();
    o.progress = [&c](double f) {
      c.report(f);
      c.check();
    };
    auto result = std::make_shared<estimation::ContactAngleResult>(estimation::run_contact_angle(*lg, *d.dh, o));
    return [this, result] {
      for (const auto& s : result->estimates.streams()) {
        if (input_->log.find_stream(s.name()) == nullptr) input_->log.add_stream(s);
      }
      input_->contact = *result;
      const double t = time_;
      rebuild_tree();
      rebuild_views();
      select_tab("Contact angles");
      set_time(t);
    };
  });
}

void MainWindow::install(std::unique_ptr<ViewInput> in) {
  play_->setChecked(false);
  if (rover_) rover_widget_->renderWindow()->RemoveRenderer(rover_->renderer());
  rover_.reset();
  if (planar_) rover_widget_->renderWindow()->RemoveRenderer(planar_->renderer());
  planar_.reset();
  if (contact_) {
    for (const auto& r : contact_->renderers()) contact_widget_->renderWindow()->RemoveRenderer(r);
  }
  contact_.reset();
  plot_channels_.clear();
  input_ = std::move(in);
  rebuild_tree();
  rebuild_views();
  rebuild_analysis();
  rebuild_surface();
  QString notes;
  for (const auto& n : input_->notes) notes += q(n) + "; ";
  status_->setText(QString("%1 loaded. %2").arg(q(input_->file), notes));
  if (input_->is_wheel_test()) select_tab("Traction surface");
  set_time(t0_);
}

void MainWindow::rebuild_tree() {
  tree_->clear();
  if (!input_) return;
  if (input_->is_wheel_test()) {
    auto* item = new QTreeWidgetItem(tree_, {"single-wheel points", "", QString::number(input_->wheel_points.size()), ""});
    item->setExpanded(true);
    return;
  }
  for (const auto& s : input_->log.streams()) {
    auto* item = new QTreeWidgetItem(tree_, {q(s.name()), "", QString::number(s.size()), QString::number(s.mean_rate_hz(), 'f', 1)});
    for (const auto& c : s.channels()) new QTreeWidgetItem(item, {q(c.name), q(c.unit), "", ""});
  }
}

void MainWindow::add_plot_channel(const QString& stream, const QString& channel) {
  if (!input_) return;
  const log::Stream* s = input_->log.find_stream(stream.toStdString());
  if (s == nullptr || s->find_channel(channel.toStdString()) == nullptr) return;
  const std::pair<std::string, std::string> ref{stream.toStdString(), channel.toStdString()};
  if (plot_channels_.empty() && chart_) {  // the first pick adds to what is shown
    for (const auto& c : chart_->channels()) plot_channels_.push_back({c.stream, c.channel});
  }
  if (std::find(plot_channels_.begin(), plot_channels_.end(), ref) != plot_channels_.end()) return;
  plot_channels_.push_back(ref);
  rebuild_views();
  set_time(time_);
}

void MainWindow::rebuild_views() {
  if (!input_ || input_->is_wheel_test()) {
    t0_ = 0;
    t1_ = 1;
    return;
  }
  const log::Log& lg = input_->log;
  // Rover: the planar side view for rocker-bogie simulations, else the 3D one.
  if (rover_) rover_widget_->renderWindow()->RemoveRenderer(rover_->renderer());
  if (planar_) rover_widget_->renderWindow()->RemoveRenderer(planar_->renderer());
  rover_.reset();
  planar_.reset();
  if (views::is_planar_rocker_bogie_log(lg)) {
    planar_ = std::make_unique<views::PlanarRoverScene>(lg);
    rover_widget_->renderWindow()->AddRenderer(planar_->renderer());
  } else {
    rover_ = std::make_unique<views::RoverScene>(lg, app::rover_geometry(lg));
    rover_widget_->renderWindow()->AddRenderer(rover_->renderer());
  }
  // Contact angles when estimated.
  if (contact_) {
    for (const auto& r : contact_->renderers()) contact_widget_->renderWindow()->RemoveRenderer(r);
    contact_.reset();
  }
  if (lg.find_stream("estimate/contact/wheels") != nullptr) {
    try {
      contact_ = std::make_unique<views::ContactAngleScene>(lg);
      for (const auto& r : contact_->renderers()) contact_widget_->renderWindow()->AddRenderer(r);
    } catch (const DataError&) {
    }
  }
  // Plots: the chosen channels, or the defaults (slip when estimated).
  std::vector<views::ChannelRef> refs;
  for (const auto& [s, c] : plot_channels_) refs.push_back({s, c});
  if (refs.empty()) {
    const log::Stream* slip = lg.find_stream("estimate/ins/slip");
    if (slip != nullptr && slip->find_channel("reference_slip") != nullptr) {
      refs = {{"estimate/ins/slip", "slip_ratio"}, {"estimate/ins/slip", "reference_slip"}};
    } else {
      try {
        refs = views::default_channels(lg);
      } catch (const DataError&) {
      }
    }
  }
  if (!refs.empty()) {
    // One chart (and context view) for the widget's lifetime: its interactor
    // style keeps timers that must not outlive it.
    if (chart_) {
      chart_->reset(lg, refs);
    } else {
      chart_ = std::make_unique<views::TimeSeriesChart>(lg, refs);
      chart_->view()->SetRenderWindow(plot_widget_->renderWindow());
      chart_->view()->SetInteractor(plot_widget_->interactor());
    }
    chart_->set_window(chart_->start_time(), chart_->end_time(), static_cast<std::size_t>(std::max(400, plot_widget_->width())));
  }
  // Timeline over every stream.
  bool first = true;
  for (const auto& s : lg.streams()) {
    if (s.empty()) continue;
    t0_ = first ? s.start_time() : std::min(t0_, s.start_time());
    t1_ = first ? s.end_time() : std::max(t1_, s.end_time());
    first = false;
  }
  if (!(t1_ > t0_)) t1_ = t0_ + 1.0;
}

void MainWindow::rebuild_analysis() {
  confusion_->clearContents();
  candidates_->setRowCount(0);
  if (!input_) return;
  QString text;
  if (input_->ins) {
    const auto& m = input_->ins->metrics;
    if (m.has_reference) {
      text += QString("INS + pseudo-measurements: final error %1 m, RMSE %2 m against GPS over %3 m; wheel odometry "
                      "final error %4 m. Velocity RMSE %5 m/s, heading drift %6 deg.\n")
                  .arg(m.final_position_error, 0, 'f', 2).arg(m.position_rmse, 0, 'f', 2).arg(m.distance, 0, 'f', 1)
                  .arg(input_->ins->odometry.final_position_error, 0, 'f', 2).arg(m.velocity_rmse, 0, 'f', 3)
                  .arg(m.heading_drift * 180.0 / M_PI, 0, 'f', 2);
    }
    if (m.confusion.total() > 0) {
      text += QString("Slip-class accuracy %1 % of %2 samples.\n").arg(100.0 * m.confusion.accuracy(), 0, 'f', 1).arg(m.confusion.total());
      for (int e = 0; e < estimation::kSlipClasses; ++e) {
        for (int t = 0; t < estimation::kSlipClasses; ++t) {
          const double f = m.confusion.fraction(e, t);
          auto* item = new QTableWidgetItem(std::isfinite(f) ? QString("%1 %").arg(100.0 * f, 0, 'f', 1) : "-");
          if (std::isfinite(f)) item->setBackground(QColor::fromRgbF(1.0 - 0.5 * f, 1.0 - 0.5 * f, 1.0));
          confusion_->setItem(e, t, item);
        }
      }
    }
  }
  if (input_->odometry) {
    const auto& r = *input_->odometry;
    text += q(r.what_is_wrong) + "\n" + q(r.verdict);
    candidates_->setRowCount(static_cast<int>(r.candidates.size()) + 1);
    auto row = [&](int i, const QString& name, const QString& fitted, double fit, double held, double fin, bool bold) {
      const QStringList cells{name, fitted, QString::number(fit, 'f', 2), QString::number(held, 'f', 2), QString::number(fin, 'f', 2)};
      for (int k = 0; k < cells.size(); ++k) {
        auto* item = new QTableWidgetItem(cells[k]);
        if (bold) {
          QFont font = item->font();
          font.setBold(true);
          item->setFont(font);
        }
        candidates_->setItem(i, k, item);
      }
    };
    row(0, "(nominal geometry)", "", r.baseline_fit_rmse, r.baseline_held_out_rmse, r.baseline_held_out_final, false);
    for (std::size_t i = 0; i < r.candidates.size(); ++i) {
      const auto& c = r.candidates[i];
      QString fitted;
      for (const auto& p : c.parameters) fitted += q(p.name) + " = " + QString::number(p.value, 'g', 4) + "  ";
      row(static_cast<int>(i) + 1, q(c.name), fitted, c.fit_rmse, c.held_out_rmse, c.held_out_final, static_cast<int>(i) == r.best);
    }
  }
  if (text.isEmpty()) text = "No analyses yet: the log needs imu and wheels (and gps for the metrics).";
  analysis_text_->setText(text);
}

void MainWindow::rebuild_surface() {
  if (!input_) return;
  auto* window = surface_widget_->renderWindow();
  while (window->GetRenderers()->GetFirstRenderer() != nullptr) {
    window->RemoveRenderer(window->GetRenderers()->GetFirstRenderer());
  }
  std::optional<std::string> soil;
  if (surface_soil_->currentIndex() > 0) soil = surface_soil_->currentText().toStdString();
  try {
    const views::TractionSurfaceData d =
        app::traction_surface_of(*input_, surface_quantity_->currentText().toStdString(), soil);
    const views::TractionSurfaceScene scene = views::make_traction_surface_scene(d);
    window->AddRenderer(scene.renderer);
    surface_note_->setText(QString("%1: %2 points").arg(q(d.quantity)).arg(d.points.size()));
  } catch (const std::exception& e) {
    surface_note_->setText(QString("Nothing to draw: ") + e.what());
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
  if (rover_) rover_->set_time(time_);
  if (planar_) planar_->set_time(time_);
  if (chart_) chart_->set_cursor(time_);
  if (contact_) contact_->set_time(time_);
  render_views();
  emit time_changed(time_);
}

void MainWindow::render_views() {
  // Coalesced: however fast the timeline moves, the visible view renders at
  // most about 60 times a second, and hidden views not at all.
  if (!render_timer_->isActive()) render_timer_->start();
}

void MainWindow::render_now() {
  QWidget* page = tabs_->currentWidget();
  if (page == rover_widget_ && (rover_ || planar_)) rover_widget_->renderWindow()->Render();
  if (page == plot_widget_ && chart_) plot_widget_->renderWindow()->Render();
  if (page == contact_widget_ && contact_) contact_widget_->renderWindow()->Render();
}

void MainWindow::select_tab(const QString& name) {
  for (int i = 0; i < tabs_->count(); ++i) {
    if (tabs_->tabText(i) == name) tabs_->setCurrentIndex(i);
  }
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
  QSettings settings;
  settings.setValue("window/geometry", saveGeometry());
  settings.setValue("window/state", saveState());
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
