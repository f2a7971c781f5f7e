#include "app/gui/job_runner.h"

#include <QtConcurrent/QtConcurrent>

#include <cerrno>
#include <exception>

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

namespace roverlab::gui {

namespace {

// Raises the calling thread's nice value to at least `nice` (Linux: per thread).
void run_nicer(int nice) {
  const auto tid = static_cast<id_t>(syscall(SYS_gettid));
  errno = 0;
  const int now = getpriority(PRIO_PROCESS, tid);
  if (errno == 0 && now < nice) setpriority(PRIO_PROCESS, tid, nice);
}

}  // namespace

JobRunner::JobRunner(QObject* parent) : QObject(parent) {
  pool_.setMaxThreadCount(1);
  connect(&watcher_, &QFutureWatcher<Outcome>::finished, this, &JobRunner::on_finished);
  poll_.setInterval(50);
  connect(&poll_, &QTimer::timeout, this, [this] { emit progress(progress_.load()); });
}

JobRunner::~JobRunner() {
  cancel();
  wait();
}

bool JobRunner::start(const QString& title, Work work) {
  if (running_) return false;
  running_ = true;
  drop_result_ = false;
  title_ = title;
  progress_.store(0.0);
  cancel_.store(false);
  JobControl control(&progress_, &cancel_);
  watcher_.setFuture(QtConcurrent::run(&pool_, [work = std::move(work), control]() -> Outcome {
    run_nicer(kJobNice);
    Outcome o;
    try {
      o.apply = work(control);
      if (control.cancelled()) o.error = "cancelled";
    } catch (const Cancelled&) {
      o.error = "cancelled";
    } catch (const std::exception& e) {
      o.error = e.what();
    } catch (...) {
      o.error = "unknown error";
    }
    return o;
  }));
  poll_.start();
  emit started(title);
  return true;
}

void JobRunner::wait() {
  if (!running_) return;
  drop_result_ = true;
  watcher_.waitForFinished();
  // finished() is delivered through the event loop; settle the state here.
  poll_.stop();
  running_ = false;
}

void JobRunner::on_finished() {
  poll_.stop();
  const bool dropped = drop_result_;
  running_ = false;
  if (dropped) return;
  Outcome o = watcher_.result();
  QString error = QString::fromStdString(o.error);
  if (error.isEmpty() && o.apply) {
    try {
      o.apply();
    } catch (const std::exception& e) {
      error = e.what();
    }
  }
  emit progress(1.0);
  emit finished(title_, error);
}

}  // namespace roverlab::gui
