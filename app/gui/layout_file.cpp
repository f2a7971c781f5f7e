#include "app/gui/layout_file.h"

#include <QDataStream>
#include <QString>

#include <cstdint>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "core/common/error.h"
#include "importers/atomic_file.h"
#include "importers/json_resource.h"

namespace roverlab::gui {

namespace {

constexpr int kVersion = 2;
constexpr std::size_t kMaxBytes = 16u << 20;  // a layout is a few kB: refuse to read a large file whole
constexpr std::size_t kMaxPlotPanes = 32;
constexpr std::size_t kMaxPaneChannels = 256;

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

// The {"stream", "channel"} entries that name both, each once; others are
// skipped. More than kMaxPaneChannels distinct curves are no layout (a pane
// listing one channel 100,000 times took gigabytes).
std::vector<std::pair<std::string, std::string>> channels_of(const nlohmann::json& list, const std::string& path) {
  std::vector<std::pair<std::string, std::string>> out;
  if (!list.is_array()) return out;
  std::set<std::pair<std::string, std::string>> seen;
  for (const auto& p : list) {
    if (p.is_object() && p.contains("stream") && p.contains("channel") && p.at("stream").is_string() &&
        p.at("channel").is_string() && !p.at("stream").get<std::string>().empty() &&
        !p.at("channel").get<std::string>().empty()) {
      std::pair<std::string, std::string> channel(p.at("stream").get<std::string>(),
                                                  p.at("channel").get<std::string>());
      if (!seen.insert(channel).second) continue;
      if (out.size() == kMaxPaneChannels) {
        throw InputError(path,
                         "a plot pane of the layout lists more than " + std::to_string(kMaxPaneChannels) + " channels");
      }
      out.push_back(std::move(channel));
    }
  }
  return out;
}

// QMainWindow::saveState's dock part, as Qt 5 writes it (qdockarealayout.cpp):
// an area's info is a sequence or tab marker, an orientation and its items,
// each a widget (name, flags, place) or a nested info. Qt reads an area's
// index without a bound check (77 crashes it), so every index is checked here.
class WindowStateCheck {
 public:
  explicit WindowStateCheck(const QByteArray& state) : in_(state) {}

  bool sound() {
    qint32 marker = 0;
    qint32 version = 0;
    in_ >> marker >> version;
    if (!ok() || marker != 0xff) return false;
    while (!in_.atEnd()) {
      const quint8 section = byte();
      if (section == kDockAreas) {
        if (!dock_areas()) return false;
      } else if (section == kFloatingTabs) {
        qint32 rect[4];
        in_ >> rect[0] >> rect[1] >> rect[2] >> rect[3];
        if (!info(0)) return false;
      } else {
        return ok();  // the tool bars' part, which Qt checks itself
      }
    }
    return ok();
  }

 private:
  static constexpr quint8 kDockAreas = 0xfd, kFloatingTabs = 0xf9, kSequence = 0xfc, kTab = 0xfa, kWidget = 0xfb;
  static constexpr int kMaxDepth = 16;
  static constexpr qint32 kMaxItems = 1000;

  bool ok() const { return in_.status() == QDataStream::Ok; }
  quint8 byte() {
    quint8 b = 0;
    in_ >> b;
    return b;
  }

  bool dock_areas() {
    qint32 count = 0;
    in_ >> count;
    if (!ok() || count < 0 || count > 4) return false;
    bool seen[4] = {false, false, false, false};
    for (qint32 k = 0; k < count; ++k) {
      qint32 area = 0;
      qint32 size[2];
      in_ >> area >> size[0] >> size[1];
      if (!ok() || area < 0 || area > 3 || seen[area]) return false;
      seen[area] = true;
      if (!info(0)) return false;
    }
    qint32 rest[6];  // the central widget's size, the four corners
    for (qint32& v : rest) in_ >> v;
    return ok();
  }

  bool info(int depth) {
    const quint8 marker = byte();
    if (!ok() || depth > kMaxDepth || (marker != kSequence && marker != kTab)) return false;
    qint32 index = 0;
    if (marker == kTab) in_ >> index;
    const quint8 orientation = byte();
    qint32 count = 0;
    in_ >> count;
    if (!ok() || orientation < 1 || orientation > 2 || count < 0 || count > kMaxItems) return false;
    for (qint32 k = 0; k < count; ++k) {
      if (!item(depth)) return false;
    }
    return ok();
  }

  bool item(int depth) {
    const quint8 marker = byte();
    qint32 place[4];
    if (marker == kWidget) {
      QString name;
      quint8 flags = 0;
      in_ >> name >> flags;
      for (qint32& v : place) in_ >> v;
      return ok();
    }
    if (marker != kSequence) return false;
    for (qint32& v : place) in_ >> v;
    return ok() && info(depth + 1);
  }

  QDataStream in_;
};

std::string text_of(const nlohmann::json& doc, const char* key) {
  return doc.contains(key) && doc.at(key).is_string() ? doc.at(key).get<std::string>() : std::string();
}

}  // namespace

bool window_state_is_sound(const QByteArray& state) { return WindowStateCheck(state).sound(); }

LayoutFile read_layout(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot read the layout");
  std::string text(kMaxBytes + 1, '\0');
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (text.size() > kMaxBytes) throw InputError(path, "not a RoverLab layout (larger than 16 MB)");
  const nlohmann::json doc = io::parse_bounded_json(text);
  if (!doc.is_object() || text_of(doc, "format") != "roverlab-layout") {
    throw InputError(path, "not a RoverLab layout (a JSON file of format roverlab-layout)");
  }
  // The number as written (1099511627776 is not "version 0", 4294967298 not version 2).
  const nlohmann::json& given = doc.contains("version") ? doc.at("version") : nlohmann::json(1);
  if (!given.is_number_integer() || given.get<std::int64_t>() < 1 || given.get<std::int64_t>() > kVersion) {
    throw InputError(path, "layout version " + given.dump() + ": this RoverLab reads versions 1 and 2");
  }
  const int version = static_cast<int>(given.get<std::int64_t>());
  LayoutFile layout;
  // Version 1 always held the window's state; version 2 may leave it out (a layout written by hand).
  if (version == 1 && text_of(doc, "window_state").empty()) {
    throw InputError(path, "not a RoverLab layout (a JSON file of format roverlab-layout)");
  }
  layout.window_state = QByteArray::fromBase64(QByteArray::fromStdString(text_of(doc, "window_state")));
  if (!layout.window_state.isEmpty() && !window_state_is_sound(layout.window_state)) {
    throw InputError(path, "the layout's window state is damaged (not as Qt writes a window's dock areas)");
  }
  if (doc.contains("panes_in_front") && doc.at("panes_in_front").is_array()) {
    for (const auto& title : doc.at("panes_in_front")) {
      if (title.is_string()) layout.panes_in_front.push_back(title.get<std::string>());
    }
  }
  if (version == 1 || !doc.contains("plot_panes")) {  // one Plots pane
    layout.plot_panes.push_back({"pane/timeseries", "Plots", channels_of(doc.value("plots", nlohmann::json()), path)});
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
        {text_of(p, "name"), text_of(p, "title"), channels_of(p.value("channels", nlohmann::json()), path)});
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
