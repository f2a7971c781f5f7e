// MainWindow's plot panes and layouts: several plot panes side by side (View >
// New plot pane), each a drop target for channels dragged from the streams
// tree and each with its own channels; the time window the user zooms to in
// one followed by all; the layout file records every plot pane and its
// channels (app/gui/layout_file.h) and re-creates them on another log.
#include <QVTKOpenGLNativeWidget.h>
#include <QAction>
#include <QDockWidget>
#include <QDropEvent>
#include <QLabel>
#include <QMenu>
#include <QMimeData>
#include <QStackedWidget>
#include <QTimer>

#include <algorithm>

#include "app/gui/layout_file.h"
#include "app/gui/main_window.h"
#include "core/common/error.h"
#include "core/estimation/ins_slip/streams.h"
#include "views/timeseries_chart.h"
#include "views/view.h"

namespace roverlab::gui {

namespace {

constexpr const char* kPlotsName = "pane/timeseries";

}  // namespace

QDockWidget* MainWindow::new_plot_pane(const QString& name, const QString& title) {
  const views::View* plots = views::find_view("timeseries");
  if (plots == nullptr) return nullptr;
  QString pane = name;
  int n = 2;
  for (; pane.isEmpty(); ++n) {  // the first number no pane has
    if (plot_tab_named(QString("%1/%2").arg(kPlotsName).arg(n).toStdString()) == nullptr)
      pane = QString("%1/%2").arg(kPlotsName).arg(n);
  }
  const QString shown = title.isEmpty() ? "Plots " + pane.section('/', -1) : title;
  // Beside the last plot pane docked and shown (right of it), else beside the panes.
  QDockWidget* beside = nullptr;
  for (const auto& tab : view_tabs_) {
    if (tab.view->uses_channels() && !tab.dock->isHidden() && !tab.dock->isFloating()) beside = tab.dock;
  }
  ViewTab& tab = add_pane(*plots, pane, shown);
  tab.added = true;
  QDockWidget* dock = tab.dock;
  if (beside != nullptr && !tabifiedDockWidgets(beside).isEmpty()) {
    // Out of its tab group, below it: a row of plots side by side under the
    // views (plots are wide and low). Qt would tab a dock split from a tabbed one.
    removeDockWidget(beside);
    addDockWidget(Qt::RightDockWidgetArea, beside, Qt::Vertical);
    beside->show();
  }
  if (beside != nullptr) splitDockWidget(beside, dock, Qt::Horizontal);
  spread_plot_panes();
  // Again once Qt has laid the new dock out, unless a layout's own arrangement came since.
  spread_pending_ = true;
  QTimer::singleShot(0, this, [this] {
    if (spread_pending_) spread_plot_panes();
    spread_pending_ = false;
  });
  if (view_menu_ != nullptr) view_menu_->insertAction(analysis_dock_->toggleViewAction(), dock->toggleViewAction());
  plot_target_ = view_tabs_.size() - 1;
  if (input_ && !input_->is_wheel_test()) {
    rebuild_view(view_tabs_.back());
  } else if (input_) {
    tab.why->setText("Nothing to show: " + QString::fromStdString(input_->file) + " is a single-wheel test table.");
  } else {
    tab.why->setText("Nothing to show yet: open a log, then drag channels from the Streams tree onto this pane.");
  }
  dock->show();
  dock->raise();
  return dock;
}

// The plot panes in a row share its width; the row takes 45 % of the
// height under the views' tab group.
void MainWindow::spread_plot_panes() {
  QList<QDockWidget*> row;
  QDockWidget* group = nullptr;
  for (const auto& tab : view_tabs_) {
    if (tab.dock->isHidden() || tab.dock->isFloating()) continue;
    if (!tab.view->uses_channels() || !tabifiedDockWidgets(tab.dock).isEmpty()) {
      if (group == nullptr) group = tab.dock;
    } else {
      row << tab.dock;
    }
  }
  if (row.isEmpty()) return;
  int rest = width();
  if (auto* streams = findChild<QDockWidget*>("streams"); streams != nullptr && !streams->isHidden()) {
    // The streams keep their column; the right area (the views and the plots) the rest.
    const int column = std::min(330, width() / 4);
    rest -= column;
    resizeDocks({streams, group != nullptr ? group : row.front()}, {column, rest}, Qt::Horizontal);
  }
  // (One call per area: Qt shares a list that spans the areas unevenly.)
  QList<int> widths;
  for (int i = 0; i < row.size(); ++i) widths << rest / static_cast<int>(row.size());
  resizeDocks(row, widths, Qt::Horizontal);
  if (group != nullptr) resizeDocks({group, row.front()}, {height() * 55 / 100, height() * 45 / 100}, Qt::Vertical);
}

QStringList MainWindow::plot_pane_titles() const {
  QStringList titles;
  for (const auto& tab : view_tabs_) {
    if (tab.view->uses_channels()) titles << tab.dock->windowTitle();
  }
  return titles;
}

views::TimeSeriesChart* MainWindow::chart(const QString& title) const {
  for (const auto& tab : view_tabs_) {
    if (tab.dock->windowTitle() == title) return dynamic_cast<views::TimeSeriesChart*>(tab.scene.get());
  }
  return nullptr;
}

MainWindow::ViewTab* MainWindow::plot_tab_named(const std::string& name) {
  for (auto& tab : view_tabs_) {
    if (tab.view->uses_channels() && tab.dock->objectName().toStdString() == name) return &tab;
  }
  return nullptr;
}

void MainWindow::fit_plots() {
  for (auto& tab : view_tabs_) {
    if (auto* c = dynamic_cast<views::TimeSeriesChart*>(tab.scene.get())) {
      c->zoom_to_fit();
      tab.stale = true;
    }
  }
  render_views();
}

void MainWindow::follow_window(std::size_t k, double t0, double t1) {
  for (std::size_t i = 0; i < view_tabs_.size(); ++i) {
    auto* c = dynamic_cast<views::TimeSeriesChart*>(view_tabs_[i].scene.get());
    if (i == k || c == nullptr) continue;
    c->show_window(t0, t1);
    view_tabs_[i].stale = true;
  }
  render_views();
}

void MainWindow::plot_input(const ViewTab& tab, views::SceneInput& in) const {
  for (const auto& [s, c] : tab.channels) in.channels.push_back({s, c});
  if (!in.channels.empty() || tab.added) return;
  // The Plots pane by default: the slip when estimated, or the view's defaults.
  const log::Stream* slip = in.log->find_stream(estimation::ins_streams::kSlip);
  if (slip != nullptr && slip->find_channel("reference_slip") != nullptr) {
    in.channels = {{estimation::ins_streams::kSlip, "slip_ratio"}, {estimation::ins_streams::kSlip, "reference_slip"}};
  }
}

std::string MainWindow::empty_plot_note(const ViewTab& tab) {
  std::string lacks;
  for (const auto& [stream, channel] : tab.wanted) lacks += (lacks.empty() ? "" : ", ") + stream + ":" + channel;
  const std::string drag = "Drag channels (or a whole stream) from the Streams tree onto this pane.";
  if (lacks.empty()) return "nothing plotted yet. " + drag;
  return "this log lacks the layout's channels for it (" + lacks + "). " + drag;
}

void MainWindow::add_plot_channel(const QString& stream, const QString& channel) {
  if (plot_target_ >= view_tabs_.size()) return;
  add_plot_channels(view_tabs_[plot_target_], {{stream.toStdString(), channel.toStdString()}});
}

void MainWindow::add_plot_channels(ViewTab& tab, const std::vector<std::pair<std::string, std::string>>& channels) {
  if (!input_ || input_->is_wheel_test()) return;
  auto* shown = dynamic_cast<views::TimeSeriesChart*>(tab.scene.get());
  if (tab.channels.empty() && shown != nullptr) {  // the first pick adds to what is shown
    for (const auto& c : shown->channels()) tab.channels.emplace_back(c.stream, c.channel);
  }
  bool added = false;
  for (const auto& ref : channels) {
    const log::Stream* s = input_->log.find_stream(ref.first);
    if (s == nullptr || s->find_channel(ref.second) == nullptr) continue;
    if (std::find(tab.channels.begin(), tab.channels.end(), ref) != tab.channels.end()) continue;
    tab.channels.push_back(ref);
    added = true;
  }
  plot_target_ = static_cast<std::size_t>(&tab - view_tabs_.data());
  if (!added) return;
  rebuild_view(tab);
  if (tab.scene) tab.scene->set_time(time_);  // none when the pane cannot draw them (it says why)
  tab.stale = true;
  render_views();
}

// Channels dropped on a plot pane are plotted in that pane.
bool MainWindow::eventFilter(QObject* watched, QEvent* event) {
  const bool drag = event->type() == QEvent::DragEnter || event->type() == QEvent::DragMove;
  if (!drag && event->type() != QEvent::Drop) return QMainWindow::eventFilter(watched, event);
  auto* drop = static_cast<QDropEvent*>(event);
  auto* widget = qobject_cast<QWidget*>(watched);
  const auto on = std::find_if(view_tabs_.begin(), view_tabs_.end(), [&](const ViewTab& tab) {
    return tab.view->uses_channels() && widget != nullptr && (widget == tab.page || tab.page->isAncestorOf(widget));
  });
  if (on == view_tabs_.end() || !drop->mimeData()->hasFormat(kChannelsMime))
    return QMainWindow::eventFilter(watched, event);
  drop->acceptProposedAction();
  if (drag) return true;
  std::vector<std::pair<std::string, std::string>> channels;
  const QStringList lines = QString::fromUtf8(drop->mimeData()->data(kChannelsMime)).split('\n', Qt::SkipEmptyParts);
  for (const QString& line : lines) {
    const QStringList parts = line.split('\t');
    if (parts.size() == 2) channels.emplace_back(parts[0].toStdString(), parts[1].toStdString());
  }
  add_plot_channels(*on, channels);
  show_pane(on->page);
  return true;
}

void MainWindow::save_layout(const QString& path) const {
  LayoutFile layout;
  for (const auto& tab : view_tabs_) {
    if (!tab.view->uses_channels()) continue;
    PlotPaneLayout pane{tab.dock->objectName().toStdString(), tab.dock->windowTitle().toStdString(), tab.channels};
    const auto* shown = dynamic_cast<const views::TimeSeriesChart*>(tab.scene.get());
    if (pane.channels.empty() && shown != nullptr) {  // the defaults shown
      for (const auto& c : shown->channels()) pane.channels.emplace_back(c.stream, c.channel);
    }
    layout.plot_panes.push_back(std::move(pane));
  }
  for (const QString& title : tab_names()) {  // the panes in front of their tab groups
    if (pane(title)->isVisible() && !pane(title)->visibleRegion().isEmpty())
      layout.panes_in_front.push_back(title.toStdString());
  }
  layout.window_state = saveState();
  write_layout(path.toStdString(), layout);
}

void MainWindow::apply_layout(const QString& path) {
  const LayoutFile layout = read_layout(path.toStdString());
  // Qt restores docks by object name: every plot pane of the layout exists first.
  for (const auto& p : layout.plot_panes) {
    if (plot_tab_named(p.name) == nullptr)
      new_plot_pane(QString::fromStdString(p.name), QString::fromStdString(p.title));
  }
  if (!layout.window_state.isEmpty()) {
    if (!restoreState(layout.window_state)) {
      throw InputError(path.toStdString(), "the layout's window state cannot be read");
    }
    spread_pending_ = false;  // the panes as the layout has them
  }
  for (auto& tab : view_tabs_) {
    if (!tab.view->uses_channels()) continue;
    tab.wanted.clear();
    for (const auto& p : layout.plot_panes) {
      if (p.name == tab.dock->objectName().toStdString()) tab.wanted = p.channels;
    }
  }
  for (const auto& title : layout.panes_in_front) select_tab(QString::fromStdString(title));
  if (input_ && !input_->is_wheel_test()) {
    if (const QString missing = plot_layout_channels(); !missing.isEmpty()) status_->setText(missing);
    rebuild_views();
    set_time(time_);
  }
}

QString MainWindow::plot_layout_channels() {
  QStringList missing;
  for (auto& tab : view_tabs_) {
    if (!tab.view->uses_channels()) continue;
    tab.channels.clear();
    if (input_->is_wheel_test()) continue;
    for (const auto& [stream, channel] : tab.wanted) {
      const log::Stream* s = input_->log.find_stream(stream);
      if (s != nullptr && s->find_channel(channel) != nullptr) {
        tab.channels.emplace_back(stream, channel);
      } else {
        missing << tab.dock->windowTitle() + ": " + QString::fromStdString(stream + ":" + channel);
      }
    }
  }
  return missing.isEmpty() ? QString() : "The layout's channels this log lacks: " + missing.join(", ") + ". ";
}

}  // namespace roverlab::gui
