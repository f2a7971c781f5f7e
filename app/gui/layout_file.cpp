#include "app/gui/layout_file.h"

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/common/error.h"
#include "importers/atomic_file.h"

namespace roverlab::gui {

namespace {

constexpr int kVersion = 2;
constexpr std::size_t kMaxBytes = 16u << 20;  // a layout is a few kB: refuse to read a large file whole
constexpr std::size_t kMaxPlotPanes = 32;

// "pane/timeseries" (the Plots pane) or "pane/timeseries/N" (N = 2..999, one the user added).
bool plot_pane_name(const std::string& name) {
  const std::string base = "pane/timeseries";
  if (name == base) return true;
  if (name.rfind(base + "/", 0) != 0) return false;
  const std::string n = name.substr(base.size() + 1);
  return !n.empty() && n.size() <= 3 && n.find_first_not_of("0123456789") == std::string::npos && n[0] != '0' &&
         n != "1";
}

nlohmann::json channels_json(const std::vector<std::pair<std::string, std::string>>& channels) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& [stream, channel] : channels) out.push_back({{"stream", stream}, {"channel", channel}});
  return out;
}

// The {"stream", "channel"} entries that name both; others are skipped.
std::vector<std::pair<std::string, std::string>> channels_of(const nlohmann::json& list) {
  std::vector<std::pair<std::string, std::string>> out;
  if (!list.is_array()) return out;
  for (const auto& p : list) {
    if (p.is_object() && p.contains("stream") && p.contains("channel") && p.at("stream").is_string() &&
        p.at("channel").is_string() && !p.at("stream").get<std::string>().empty() &&
        !p.at("channel").get<std::string>().empty()) {
      out.emplace_back(p.at("stream").get<std::string>(), p.at("channel").get<std::string>());
    }
  }
  return out;
}

std::string text_of(const nlohmann::json& doc, const char* key) {
  return doc.contains(key) && doc.at(key).is_string() ? doc.at(key).get<std::string>() : std::string();
}

}  // namespace

LayoutFile read_layout(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot read the layout");
  std::string text(kMaxBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > kMaxBytes) throw InputError(path, "not a RoverLab layout (larger than 16 MB)");
  const nlohmann::json doc = nlohmann::json::parse(text, nullptr, false);
  if (!doc.is_object() || text_of(doc, "format") != "roverlab-layout") {
    throw InputError(path, "not a RoverLab layout (a JSON file of format roverlab-layout)");
  }
  const int version =
      doc.contains("version") && doc.at("version").is_number_integer() ? doc.at("version").get<int>() : 1;
  if (version < 1 || version > kVersion) {
    throw InputError(path, "layout version " + std::to_string(version) + ": this RoverLab reads versions 1 and 2");
  }
  LayoutFile layout;
  // Version 1 always held the window's state; version 2 may leave it out (a layout written by hand).
  if (version == 1 && text_of(doc, "window_state").empty()) {
    throw InputError(path, "not a RoverLab layout (a JSON file of format roverlab-layout)");
  }
  layout.window_state = QByteArray::fromBase64(QByteArray::fromStdString(text_of(doc, "window_state")));
  if (doc.contains("panes_in_front") && doc.at("panes_in_front").is_array()) {
    for (const auto& title : doc.at("panes_in_front")) {
      if (title.is_string()) layout.panes_in_front.push_back(title.get<std::string>());
    }
  }
  if (version == 1 || !doc.contains("plot_panes")) {  // one Plots pane
    layout.plot_panes.push_back({"pane/timeseries", "Plots", channels_of(doc.value("plots", nlohmann::json()))});
    return layout;
  }
  if (!doc.at("plot_panes").is_array()) throw InputError(path, "the layout's plot_panes is not a list");
  if (doc.at("plot_panes").size() > kMaxPlotPanes) {
    throw InputError(path, "the layout has more than " + std::to_string(kMaxPlotPanes) + " plot panes");
  }
  for (const auto& p : doc.at("plot_panes")) {
    if (!p.is_object() || !plot_pane_name(text_of(p, "name"))) {
      throw InputError(path, "a plot pane of the layout is not named pane/timeseries or pane/timeseries/N");
    }
    layout.plot_panes.push_back(
        {text_of(p, "name"), text_of(p, "title"), channels_of(p.value("channels", nlohmann::json()))});
  }
  return layout;
}

void write_layout(const std::string& path, const LayoutFile& layout) {
  nlohmann::json panes = nlohmann::json::array();
  for (const auto& p : layout.plot_panes) {
    panes.push_back({{"name", p.name}, {"title", p.title}, {"channels", channels_json(p.channels)}});
  }
  const nlohmann::json doc = {{"format", "roverlab-layout"},
                              {"version", kVersion},
                              {"panes_in_front", layout.panes_in_front},
                              {"plot_panes", panes},
                              {"plots", channels_json(layout.plot_panes.empty() ? decltype(PlotPaneLayout::channels){}
                                                                                : layout.plot_panes.front().channels)},
                              {"window_state", layout.window_state.toBase64().toStdString()}};
  io::write_text_atomically(path, doc.dump(2) + "\n");
}

}  // namespace roverlab::gui
