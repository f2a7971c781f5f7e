#pragma once
// A pool of threads sized by the machine, for work inside a study whose
// parts are independent (candidate screens, held-out folds, the two slip
// readings). Each part writes only its own result and results are combined
// in index order afterwards, so a study gives bit-identical results on any
// number of threads. The calling thread works too, and a part may itself
// run parts on the pool: a thread whose call still waits for parts other
// threads are running runs the pool's other open parts meanwhile (the
// newest first), so nesting neither deadlocks nor idles a thread.

#include <cstddef>
#include <functional>
#include <memory>

namespace roverlab {

class ThreadPool {
 public:
  // `threads` in all, the caller included (1: everything runs on the caller).
  explicit ThreadPool(std::size_t threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  std::size_t threads() const;
  // Runs work(0) .. work(n - 1), in any order and on any thread, and returns
  // when all have ended; then rethrows the exception of the lowest index that threw.
  void for_each_index(std::size_t n, const std::function<void(std::size_t)>& work);
  // Runs `background` on the pool beside `foreground` on the calling thread
  // (which may report progress or be cancelled); returns when both have
  // ended, then rethrows foreground's exception, else background's.
  void run_beside(const std::function<void()>& background, const std::function<void()>& foreground);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// The threads the machine offers (std::thread::hardware_concurrency), or
// ROVERLAB_THREADS when it is set to a whole number >= 1 (a larger one is not
// limited). Throws std::invalid_argument naming ROVERLAB_THREADS for another value.
std::size_t default_thread_count();

// The pool studies use: default_thread_count() threads until
// set_thread_count() (the --threads option) chooses another number.
ThreadPool& shared_thread_pool();
// Replaces the shared pool by one of `threads` (>= 1); call it while no work runs on it.
void set_thread_count(std::size_t threads);

}  // namespace roverlab
