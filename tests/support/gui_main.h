#pragma once
// What the tests that open RoverLab's Qt windows share: waiting on the
// event loop, and their main(): a display (a
// private Xvfb when none is set), QSettings away from the user's, no
// multisampling (under Xvfb every sample is drawn in software), VTK's
// OpenGL format before the QApplication.

#include <QVTKOpenGLNativeWidget.h>
#include <gtest/gtest.h>
#include <vtkOpenGLRenderWindow.h>

#include <QApplication>
#include <QElapsedTimer>
#include <QStandardPaths>
#include <QSurfaceFormat>
#include <QThread>
#include <functional>
#include <string>

#include "views/x_display.h"

namespace roverlab::test {

// Processes Qt events until done() holds; false after timeout_ms.
inline bool wait_until(const std::function<bool()>& done, int timeout_ms) {
  QElapsedTimer clock;
  clock.start();
  while (!done()) {
    if (clock.elapsed() > timeout_ms) return false;
    QCoreApplication::processEvents(QEventLoop::AllEvents, 20);
    QThread::msleep(2);
  }
  return true;
}

inline int run_gui_tests(int argc, char** argv) {
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

}  // namespace roverlab::test
