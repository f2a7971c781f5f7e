// `roverlab gui [FILE]`: the desktop application. With --screenshot it opens
// FILE, waits for its jobs, shows the given time and tab, saves a picture of
// the whole window and exits (headless: a private Xvfb when DISPLAY is unset).
#include <QVTKOpenGLNativeWidget.h>
#include <vtkOpenGLRenderWindow.h>
#include <QApplication>
#include <QDir>
#include <QPixmap>
#include <QSurfaceFormat>
#include <QTimer>
#include <QtGlobal>

#include <cstdio>
#include <cstdlib>

#include <CLI/CLI.hpp>

#include "app/command.h"
#include "app/command_support.h"
#include "app/commands.h"
#include "app/gui/main_window.h"
#include "core/common/library_messages.h"
#include "importers/atomic_file.h"
#include "views/x_display.h"

namespace roverlab::app {

struct GuiOptions {
  std::optional<std::string> file;
  std::optional<std::string> mapping;
  std::optional<std::string> screenshot;  // save the window as PNG and exit
  std::optional<double> time;
  std::optional<std::string> tab;      // a pane's title: Rover, Map, Plots, Traction surface, Analysis
  std::optional<std::string> layout;   // a layout file (View > Save layout) applied before FILE opens
  std::optional<std::string> compare;  // another run compared with FILE once it is open (File > Compare with...)
  int width = 1400, height = 900;
};

namespace {

// Qt's own messages (a missing XDG_RUNTIME_DIR, xcb warnings) only with --verbose:
// RoverLab's one-line errors come first and alone.
void quiet_qt_message(QtMsgType type, const QMessageLogContext& context, const QString& message) {
  if (!library_messages_verbose() && type != QtFatalMsg) return;
  (void)context;
  std::fprintf(stderr, "%s\n", message.toLocal8Bit().constData());
}

}  // namespace

int run_gui(const GuiOptions& o) {
  qInstallMessageHandler(quiet_qt_message);
  if (o.screenshot) {
    views::ensure_display();
  } else {
    const char* d = std::getenv("DISPLAY");
    if (d == nullptr || *d == '\0') {
      throw views::EnvironmentError("no X display for the GUI: set DISPLAY (or use --screenshot, which runs headless)");
    }
  }
  // No multisampling: under Xvfb every sample is drawn in software.
  vtkOpenGLRenderWindow::SetGlobalMaximumNumberOfMultiSamples(0);
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  int argc = 1;
  char name[] = "roverlab";
  char* argv[] = {name, nullptr};
  QApplication app(argc, argv);
  QApplication::setOrganizationName("RoverLab");
  QApplication::setApplicationName("RoverLab");
  gui::MainWindow window;
  if (o.screenshot) {
    window.set_quiet(true);
    window.set_keeps_settings(false);  // a batch picture: the user's recent files and folders stay as they were
    window.resize(o.width, o.height);
  }
  if (o.layout) window.apply_layout(QString::fromStdString(*o.layout));  // it may add plot panes
  if (o.tab && !window.tab_names().contains(QString::fromStdString(*o.tab))) {
    throw UsageError("--tab " + *o.tab + ": expected one of " + window.tab_names().join(", ").toStdString());
  }
  int code = kSuccess;
  window.show();
  if (o.file) {
    window.open_file(QString::fromStdString(*o.file),
                     o.mapping ? std::optional<QString>(QString::fromStdString(*o.mapping)) : std::nullopt);
  }
  if (o.compare && o.file) {  // once FILE is open and its analyses are done
    auto* later = new QTimer(&window);
    QObject::connect(later, &QTimer::timeout, &window, [&window, later, &o] {
      if (!window.last_error().isEmpty()) later->stop();
      if (!window.has_log() || window.busy()) return;
      later->stop();
      window.compare_with(QString::fromStdString(*o.compare));
    });
    later->start(100);
  }
  if (o.screenshot) {
    // Poll until the load and the estimator are done, then take the picture.
    auto* poll = new QTimer(&window);
    int waited = 0;
    QObject::connect(poll, &QTimer::timeout, &window, [&] {
      waited += 100;
      if (!window.last_error().isEmpty()) {
        std::fprintf(stderr, "roverlab: %s\n", window.last_error().toStdString().c_str());
        code = kBadInput;
        app.quit();
        return;
      }
      const bool ready = !o.file || (window.has_log() && !window.busy() && (!o.compare || window.compared_count() > 0));
      if (!ready && waited < 120000) return;
      poll->stop();
      if (o.tab) window.select_tab(QString::fromStdString(*o.tab));
      if (o.time && o.file && !(*o.time >= window.start_time() && *o.time <= window.end_time())) {
        std::fprintf(stderr, "roverlab: --time %g s is outside the log, which spans %.2f .. %.2f s\n", *o.time,
                     window.start_time(), window.end_time());
        code = kUsageError;
        app.quit();
        return;
      }
      window.set_time(o.time ? *o.time : 0.5 * (window.start_time() + window.end_time()));
      QTimer::singleShot(500, &window, [&] {
        window.set_time(window.current_time());
        window.render_now();
        const QPixmap shot = window.grab();
        io::write_atomically(*o.screenshot, [&](const std::string& tmp) {
          if (!shot.save(QString::fromStdString(tmp), "PNG")) throw std::runtime_error("could not save the screenshot");
        });
        std::printf("wrote %s (%dx%d)\n", o.screenshot->c_str(), shot.width(), shot.height());
        app.quit();
      });
    });
    poll->start(100);
  }
  const int rc = app.exec();
  return code != kSuccess ? code : rc;
}

Commands make_gui_commands() {
  Commands commands;
  commands.push_back(make_command<GuiOptions>(
      "gui", "The desktop application (Qt + VTK)",
      [](CLI::App& cmd, GuiOptions& o) {
        cmd.add_option("FILE", o.file, "Log to open");
        cmd.add_option("--mapping,-m", o.mapping,
                       "Mapping NAME or FILE for .mat/HDF5 input (default: try the known ones)");
        cmd.add_option("--screenshot", o.screenshot,
                       "Save the window as PNG once FILE is loaded and analysed, then exit");
        cmd.add_option("--time,-t", o.time, "With --screenshot: the timeline's time, s")->check(finite_in(-1e12, 1e12));
        cmd.add_option("--tab", o.tab, "With --screenshot: the pane in front (Rover | Map | Plots | ... | Analysis)");
        cmd.add_option("--compare", o.compare,
                       "Another run of the traverse, compared with FILE (File > Compare with...)");
        cmd.add_option("--layout", o.layout, "A layout FILE (View > Save layout): panes and plotted channels");
        // As render --size: a window larger than 8192 pixels cannot be grabbed.
        cmd.add_option("--width", o.width, "Window width, 16..8192")
            ->capture_default_str()
            ->check(CLI::Range(16, 8192));
        cmd.add_option("--height", o.height, "Window height, 16..8192")
            ->capture_default_str()
            ->check(CLI::Range(16, 8192));
      },
      run_gui));
  return commands;
}

}  // namespace roverlab::app
