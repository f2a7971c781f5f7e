#pragma once
// RoverLab's main window: open a log (menu, command line, drag and drop), a
// tree of its streams and channels, a timeline (play, pause, speed,
// scrubbing) that drives every view, the rover view, linked time-series
// plots, the traction-surface view, the analysis tables; estimators run as
// background jobs with progress and cancel. Layout, recent files and the last
// folder are kept between runs (QSettings).

#include <QMainWindow>
#include <QString>

#include <map>
#include <memory>
#include <optional>

#include "app/gui/job_runner.h"
#include "app/views_input.h"

class QComboBox;
class QDockWidget;
class QLabel;
class QProgressBar;
class QPushButton;
class QSlider;
class QStackedWidget;
class QTableWidget;
class QTimer;
class QToolButton;
class QTreeWidget;
class QTreeWidgetItem;
class QVTKOpenGLNativeWidget;
class QMenu;

namespace roverlab::views {
class ContactAngleScene;
class RoverScene;
class Scene;
struct SceneInput;
class TimeSeriesChart;
class View;
}  // namespace roverlab::views

namespace roverlab::gui {

using app::ViewInput;

class MainWindow : public QMainWindow {
  Q_OBJECT
 public:
  explicit MainWindow(QWidget* parent = nullptr);
  ~MainWindow() override;

  // Loads FILE in the background (a .mat file tries the known mappings);
  // afterwards runs every registered analysis that can run on the log.
  void open_file(const QString& path, const std::optional<QString>& mapping = std::nullopt);

  // Opens FILE as another run to compare with the log (File > Compare with...):
  // its streams in the tree under its own name, the views that compare runs
  // (views::View::compares_runs) drawing it against the log on the log's
  // timeline. Opening a log drops the runs compared with the one before.
  void compare_with(const QString& path, const std::optional<QString>& mapping = std::nullopt);
  // How many runs are compared with the log.
  std::size_t compared_count() const { return compared_.size(); }
  // The scene of the pane titled `title` (nullptr when it has none).
  views::Scene* pane_scene(const QString& title) const;

  JobRunner& jobs() { return *jobs_; }
  // A job runs or is about to start (the estimator follows a load).
  bool busy() const { return jobs_->busy() || estimator_pending_; }
  // Renders the visible view now (the timeline otherwise coalesces renders).
  void render_now();
  bool has_log() const { return input_ != nullptr; }
  const ViewInput* input() const { return input_.get(); }
  double current_time() const { return time_; }
  void set_time(double t);
  double start_time() const { return t0_; }
  double end_time() const { return t1_; }
  // The scenes of the view tabs (nullptr when the log cannot feed them).
  views::RoverScene* rover_scene() const;
  views::TimeSeriesChart* chart() const;
  views::ContactAngleScene* contact_scene() const;
  // The last error shown in a dialog (empty when none).
  QString last_error() const { return last_error_; }
  // Errors go to a modal dialog unless quiet (tests, screenshots): then only to last_error.
  void set_quiet(bool quiet) { quiet_ = quiet; }
  // A batch run (--screenshot) leaves the user's settings as they were: no
  // recent file, last folder or window arrangement is written when false.
  void set_keeps_settings(bool keep) { keeps_settings_ = keep; }
  // Shows the pane titled `name` (in front of the panes tabbed with it); false when there is none.
  bool select_tab(const QString& name);
  // The panes' titles: one per registered view, then Analysis.
  QStringList tab_names() const;
  // The dockable pane titled `title` (nullptr when none): the user moves,
  // tabs, splits, floats and closes them.
  QDockWidget* pane(const QString& title) const;
  // What the pane says instead of a picture when the log cannot feed its view (empty when it draws).
  QString pane_note(const QString& title) const;
  // The arrangement of the panes and the plotted channels, as a file
  // (JSON: format roverlab-layout), written atomically.
  void save_layout(const QString& path) const;
  // Arranges the panes as the file says and plots its channels on this log
  // and the logs opened after (those a log lacks are named in the status
  // bar). Throws InputError naming the file when it is not a layout.
  void apply_layout(const QString& path);
  // Plots stream:channel in the plot pane that last took channels (at first: Plots).
  void add_plot_channel(const QString& stream, const QString& channel);
  // A new plot pane ("Plots 2", ...) beside the last one, empty until channels are dropped on it
  // (View > New plot pane); `name` and `title` as a layout gives them. Returns its dock.
  QDockWidget* new_plot_pane(const QString& name = {}, const QString& title = {});
  // The plot panes' titles, Plots first.
  QStringList plot_pane_titles() const;
  // The chart of the plot pane titled `title` (nullptr when it has none).
  views::TimeSeriesChart* chart(const QString& title) const;
  // Every plot pane: the whole time range, every value axis fitted to its data (View > Fit plots).
  void fit_plots();
  // What the streams tree drags: "stream<TAB>channel" lines; the plot pane takes a drop of it.
  static constexpr const char* kChannelsMime = "application/x-roverlab-channels";

 signals:
  void log_loaded();
  void time_changed(double t);

 protected:
  void closeEvent(QCloseEvent* event) override;
  void dragEnterEvent(QDragEnterEvent* event) override;
  void dropEvent(QDropEvent* event) override;
  bool eventFilter(QObject* watched, QEvent* event) override;

 private:
  // One pane per registered view (views/views.def): its dock, its page (the
  // VTK widget, or in its place the words saying why there is nothing to
  // show), and the scene it shows (none when the log cannot feed the view).
  struct ViewTab {
    const views::View* view = nullptr;
    QDockWidget* dock = nullptr;
    QStackedWidget* page = nullptr;
    QLabel* why = nullptr;
    QVTKOpenGLNativeWidget* widget = nullptr;
    std::unique_ptr<views::Scene> scene;
    bool available = false;                   // the log feeds the view
    int fitted_width = 0, fitted_height = 0;  // the widget's size the scene was last laid out for
    bool stale = true;                        // its picture is older than the timeline's time
    // Plot panes: the channels picked, those the last layout applied asks for,
    // and whether the user added the pane (then it plots nothing by default).
    std::vector<std::pair<std::string, std::string>> channels, wanted;
    bool added = false;
    ViewTab();
    ViewTab(ViewTab&&) noexcept;
    ~ViewTab();
  };
  template <typename T>
  T* scene_as() const;
  ViewTab* tab_where(bool (views::View::*uses)() const);

  void build_ui();
  void build_menus();
  void build_streams_dock();
  void build_view_tabs();
  // A pane for `view` (its dock named `name`, titled `title`), added to view_tabs_.
  ViewTab& add_pane(const views::View& view, const QString& name, const QString& title);
  void build_layout_menu();
  // Brings the pane holding `page` to the front.
  void show_pane(QWidget* page);
  // Each plot pane plots the layout's channels that the log has; returns a
  // sentence naming the others (empty when none).
  QString plot_layout_channels();
  ViewTab* plot_tab_named(const std::string& name);
  void spread_plot_panes();
  void add_plot_channels(ViewTab& tab, const std::vector<std::pair<std::string, std::string>>& channels);
  // The other plot panes show the time window the user chose in pane k.
  void follow_window(std::size_t k, double t0, double t1);
  // The channels the scene of plot pane `tab` plots: those picked, else its defaults.
  void plot_input(const ViewTab& tab, views::SceneInput& in) const;
  // Why a plot pane the user added plots nothing (none dropped yet, or the log lacks the layout's).
  static std::string empty_plot_note(const ViewTab& tab);
  QWidget* build_surface_page(QVTKOpenGLNativeWidget* widget);
  void build_timeline();
  void build_status_bar();
  void install(std::unique_ptr<ViewInput> input);
  // Rebuilds every view of the log; returns the page of the first view it
  // made available (nullptr when none).
  QWidget* rebuild_views();
  bool rebuild_view(ViewTab& tab);
  void rebuild_tree();
  void rebuild_analysis();
  void rebuild_surface();
  void render_views();
  static bool renders(const ViewTab& tab);
  void render_pane(ViewTab& tab);
  void render_next();
  QWidget* build_analysis_tab();
  // Runs the analyses `names` in one background job; `by_hand`: say why one cannot run.
  void run_analyses(const std::vector<std::string>& names, bool by_hand);
  void show_error(const QString& text);
  void remember_recent(const QString& path);
  void refresh_recent_menu();
  void on_tick();

  std::unique_ptr<JobRunner> jobs_;
  std::unique_ptr<ViewInput> input_;
  struct ComparedRun {
    std::string name;  // the file's name without its folder and extension
    std::unique_ptr<ViewInput> input;
  };
  std::vector<ComparedRun> compared_;
  std::vector<ViewTab> view_tabs_;
  std::size_t plot_target_ = 0;  // the plot pane a double-clicked channel goes to (view_tabs_ index)
  QDockWidget* analysis_dock_ = nullptr;
  QMenu* view_menu_ = nullptr;
  QTreeWidget* tree_ = nullptr;
  QComboBox* surface_soil_ = nullptr;
  QComboBox* surface_quantity_ = nullptr;
  QLabel* surface_note_ = nullptr;
  QStackedWidget* surface_stack_ = nullptr;  // the surface's VTK widget, or in its place why there is none
  QLabel* surface_why_ = nullptr;
  QWidget* tables_ = nullptr;  // the analyses' result tables (Presentation::tables)
  QLabel* analysis_text_ = nullptr;
  QTreeWidget* results_ = nullptr;
  QSlider* slider_ = nullptr;
  QToolButton* play_ = nullptr;
  QComboBox* speed_ = nullptr;
  QLabel* time_label_ = nullptr;
  QProgressBar* progress_ = nullptr;
  QPushButton* cancel_ = nullptr;
  QLabel* status_ = nullptr;
  QMenu* recent_menu_ = nullptr;
  QTimer* player_ = nullptr;
  QTimer* render_timer_ = nullptr;
  bool estimator_pending_ = false;
  bool spread_pending_ = false;                 // new plot panes to share the row once Qt has laid them out
  std::map<std::string, std::string> choices_;  // analysis name -> its option chosen in the Analysis menu
  double time_ = 0, t0_ = 0, t1_ = 1;
  qint64 last_tick_ms_ = 0;
  QString last_error_;
  bool quiet_ = false;
  bool keeps_settings_ = true;
};

}  // namespace roverlab::gui
