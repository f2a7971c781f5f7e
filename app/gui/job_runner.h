#pragma once
// Background jobs for the GUI: one job at a time runs on a worker thread
// (QtConcurrent, on the runner's own pool of one thread, at a lower priority
// than the GUI's: nice +kJobNice, so a busy machine takes its share from the
// job, not from the event loop), reports progress through an atomic the GUI
// polls, and can be cancelled. The job's result is a continuation run on the GUI thread,
// so results (new streams, metrics) arrive without locking the model.

#include <QFutureWatcher>
#include <QObject>
#include <QString>
#include <QThreadPool>
#include <QTimer>

#include <atomic>
#include <functional>
#include <memory>
#include <string>

namespace roverlab::gui {

// Thrown by JobControl::check() inside a job that was cancelled.
struct Cancelled {};

class JobControl {
 public:
  JobControl(std::atomic<double>* progress, std::atomic<bool>* cancel) : progress_(progress), cancel_(cancel) {}
  void report(double fraction) const { progress_->store(fraction); }
  bool cancelled() const { return cancel_->load(); }
  void check() const {
    if (cancelled()) throw Cancelled{};
  }

 private:
  std::atomic<double>* progress_;
  std::atomic<bool>* cancel_;
};

class JobRunner : public QObject {
  Q_OBJECT
 public:
  // How much nicer than the GUI thread a job's thread runs (threads it starts inherit it).
  static constexpr int kJobNice = 10;

  // Runs on the worker; returns what to do on the GUI thread with the result.
  using Work = std::function<std::function<void()>(const JobControl&)>;

  explicit JobRunner(QObject* parent = nullptr);
  ~JobRunner() override;

  // False (and nothing started) while another job runs.
  bool start(const QString& title, Work work);
  bool busy() const { return running_; }
  QString title() const { return title_; }
  void cancel() { cancel_.store(true); }
  // Blocks until the running job (if any) has ended; its continuation is dropped.
  void wait();

 signals:
  void started(const QString& title);
  void progress(double fraction);
  // error is empty on success; cancelled jobs report "cancelled".
  void finished(const QString& title, const QString& error);

 private:
  struct Outcome {
    std::function<void()> apply;
    std::string error;
  };
  void on_finished();

  QThreadPool pool_;  // one thread, niced once: no other QtConcurrent work runs on it
  QFutureWatcher<Outcome> watcher_;
  QTimer poll_;
  std::atomic<double> progress_{0.0};
  std::atomic<bool> cancel_{false};
  bool running_ = false;
  bool drop_result_ = false;
  QString title_;
};

}  // namespace roverlab::gui
