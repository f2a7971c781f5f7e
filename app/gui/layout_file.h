#pragma once
// The layout file (View > Save layout, `roverlab gui --layout FILE`): the
// panes' arrangement and every plot pane with its channels, as JSON of format
// roverlab-layout. Version 2 lists the plot panes; a version-1 file (one
// "plots" list, for the one Plots pane) is still read.

#include <QByteArray>

#include <string>
#include <utility>
#include <vector>

namespace roverlab::gui {

// One plot pane: its dock's object name ("pane/timeseries", "pane/timeseries/2"), title and channels.
struct PlotPaneLayout {
  std::string name, title;
  std::vector<std::pair<std::string, std::string>> channels;  // stream, channel
};

struct LayoutFile {
  QByteArray window_state;  // QMainWindow::saveState; empty: plot panes side by side as new
  std::vector<std::string> panes_in_front;
  std::vector<PlotPaneLayout> plot_panes;
};

// False when `state` (QMainWindow::saveState) is not as Qt 5 writes it: its
// dock areas' indexes, markers and counts are checked before Qt reads it
// (Qt indexes its four dock areas with the file's number unchecked).
bool window_state_is_sound(const QByteArray& state);

// Throws InputError naming `path` when it cannot be read or is not a layout.
LayoutFile read_layout(const std::string& path);
// Written atomically (temp + rename), as version 2 with the first pane's
// channels also as "plots" (what a version-1 reader takes).
void write_layout(const std::string& path, const LayoutFile& layout);

}  // namespace roverlab::gui
