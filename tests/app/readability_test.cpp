// What a field engineer tripped over (issue 48), read back from the widgets,
// the tables and the text: one meaning for bold in every result table, with
// a legend; headline numbers that carry the weakest slip class and say which
// frame their RMSE is in; labels that fit or elide visibly with a tooltip;
// defaults that match their help; a headless screenshot that leaves the
// user's settings file byte for byte as it was.
#include <gtest/gtest.h>

#include <QVTKOpenGLNativeWidget.h>
#include <vtkOpenGLRenderWindow.h>
#include <QApplication>
#include <QElapsedTimer>
#include <QStandardPaths>
#include <QSurfaceFormat>
#include <QThread>

#include <filesystem>
#include <functional>

#include "app/gui/main_window.h"
#include "test_support.h"
#include "views/x_display.h"

using namespace roverlab;
using namespace roverlab::test;

namespace {

const std::string kExe = ROVERLAB_EXE;
const std::string kData = ROVERLAB_TEST_DATA;
const std::string kPathfinder = kData + "/test17run.mat";

CommandResult run_roverlab(const std::string& args) { return run_command(quote(kExe) + " " + args); }

bool wait_until(const std::function<bool()>& done, int timeout_ms) {
  QElapsedTimer clock;
  clock.start();
  while (!done()) {
    if (clock.elapsed() > timeout_ms) return false;
    QCoreApplication::processEvents(QEventLoop::AllEvents, 20);
    QThread::msleep(2);
  }
  return true;
}

}  // namespace

// `roverlab gui FILE --screenshot PNG` is a batch run: the user's settings
// (recent files, last folder, window arrangement) stay byte for byte as they were.
TEST(Readability, AHeadlessScreenshotLeavesTheUsersSettingsFileAsItWas) {
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

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  // gtest_discover_tests lists the tests without a display.
  for (int i = 1; i < argc; ++i) {
    if (std::string(argv[i]).rfind("--gtest_list_tests", 0) == 0) return RUN_ALL_TESTS();
  }
  views::ensure_display();
  QStandardPaths::setTestModeEnabled(true);  // QSettings away from the user's
  vtkOpenGLRenderWindow::SetGlobalMaximumNumberOfMultiSamples(0);
  QSurfaceFormat::setDefaultFormat(QVTKOpenGLNativeWidget::defaultFormat());
  QApplication app(argc, argv);
  QApplication::setOrganizationName("RoverLabTest");
  QApplication::setApplicationName("RoverLabTest");
  return RUN_ALL_TESTS();
}
