#include "core/common/thread_pool.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdlib>
#include <deque>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace roverlab {

namespace {

// One call's parts: claimed one at a time by whichever thread is free.
struct Batch {
  const std::function<void(std::size_t)>* work = nullptr;
  std::size_t n = 0;
  std::atomic<std::size_t> next{0};
  std::mutex mutex;
  std::size_t finished = 0;
  std::atomic<bool> done{false};
  std::vector<std::exception_ptr> errors;

  bool unclaimed() const { return next.load() < n; }
  // Runs the next unclaimed part; false when every part is claimed. True
  // from the part that ends the batch is returned as `last`.
  bool run_one(bool& last) {
    last = false;
    const std::size_t i = next.fetch_add(1);
    if (i >= n) return false;
    std::exception_ptr error;
    try {
      (*work)(i);
    } catch (...) {
      error = std::current_exception();
    }
    const std::lock_guard<std::mutex> lock(mutex);
    errors[i] = error;
    if (++finished == n) {
      done = true;
      last = true;
    }
    return true;
  }
};

}  // namespace

struct ThreadPool::State {
  std::size_t threads = 1;
  std::vector<std::thread> workers;
  std::mutex mutex;
  std::condition_variable wake;  // work queued, a batch ended, or stopping
  std::deque<std::shared_ptr<Batch>> queue;
  bool stopping = false;

  // Runs one part of `batch`; when it was the batch's last, wakes the
  // threads waiting for it (under the pool's mutex: no wake-up is lost).
  bool run_part(const std::shared_ptr<Batch>& batch) {
    bool last = false;
    if (!batch->run_one(last)) {
      retire(batch);
      return false;
    }
    if (last) {
      const std::lock_guard<std::mutex> lock(mutex);
      wake.notify_all();
    }
    return true;
  }
  void work_loop() {
    for (;;) {
      std::shared_ptr<Batch> batch;
      {
        std::unique_lock<std::mutex> lock(mutex);
        wake.wait(lock, [this] { return stopping || !queue.empty(); });
        if (stopping) return;
        batch = queue.front();
      }
      run_part(batch);
    }
  }
  // Until `batch` has ended: runs the parts of other batches (the newest
  // first: the nested ones, whose caller waits for them), else sleeps. A
  // thread whose own parts are all claimed so helps the others' instead of
  // idling (a fit's evaluations while the fit beside it ends).
  void wait_helping(const std::shared_ptr<Batch>& batch) {
    for (;;) {
      std::shared_ptr<Batch> other;
      {
        std::unique_lock<std::mutex> lock(mutex);
        for (;;) {
          if (batch->done) return;
          const auto open = std::find_if(queue.rbegin(), queue.rend(), [](const auto& b) { return b->unclaimed(); });
          if (open != queue.rend()) {
            other = *open;
            break;
          }
          wake.wait(lock);
        }
      }
      run_part(other);
    }
  }
  void retire(const std::shared_ptr<Batch>& batch) {
    const std::lock_guard<std::mutex> lock(mutex);
    const auto at = std::find(queue.begin(), queue.end(), batch);
    if (at != queue.end()) queue.erase(at);
  }
  void submit(const std::shared_ptr<Batch>& batch) {
    {
      const std::lock_guard<std::mutex> lock(mutex);
      queue.push_back(batch);
    }
    wake.notify_all();
  }
};

ThreadPool::ThreadPool(std::size_t threads) : state_(std::make_unique<State>()) {
  state_->threads = std::max<std::size_t>(1, threads);
  for (std::size_t k = 1; k < state_->threads; ++k)
    state_->workers.emplace_back([s = state_.get()] { s->work_loop(); });
}

ThreadPool::~ThreadPool() {
  {
    const std::lock_guard<std::mutex> lock(state_->mutex);
    state_->stopping = true;
  }
  state_->wake.notify_all();
  for (auto& w : state_->workers) w.join();
}

std::size_t ThreadPool::threads() const { return state_->threads; }

void ThreadPool::for_each_index(std::size_t n, const std::function<void(std::size_t)>& work) {
  if (n == 0) return;
  auto batch = std::make_shared<Batch>();
  batch->work = &work;
  batch->n = n;
  batch->errors.resize(n);
  if (state_->threads == 1 || n == 1) {
    bool last = false;
    while (batch->run_one(last)) {
    }
  } else {
    state_->submit(batch);
    while (state_->run_part(batch)) {
    }
    state_->wait_helping(batch);
  }
  for (const auto& e : batch->errors) {
    if (e) std::rethrow_exception(e);
  }
}

void ThreadPool::run_beside(const std::function<void()>& background, const std::function<void()>& foreground) {
  if (state_->threads == 1) {
    foreground();
    background();
    return;
  }
  const std::function<void(std::size_t)> work = [&](std::size_t) { background(); };
  auto batch = std::make_shared<Batch>();
  batch->work = &work;
  batch->n = 1;
  batch->errors.resize(1);
  state_->submit(batch);
  std::exception_ptr error;
  try {
    foreground();
  } catch (...) {
    error = std::current_exception();
  }
  state_->run_part(batch);  // not started yet: the caller runs it
  state_->retire(batch);
  state_->wait_helping(batch);
  if (error) std::rethrow_exception(error);
  if (batch->errors[0]) std::rethrow_exception(batch->errors[0]);
}

std::size_t default_thread_count() {
  const std::size_t machine = std::max(1U, std::thread::hardware_concurrency());
  const char* text = std::getenv("ROVERLAB_THREADS");
  if (text == nullptr || *text == '\0') return machine;
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  if (*end != '\0' || value < 1 || value > 4096) {
    throw std::invalid_argument(std::string("ROVERLAB_THREADS=") + text + ": expected a whole number of threads >= 1");
  }
  return static_cast<std::size_t>(value);
}

namespace {

std::mutex& pool_mutex() {
  static std::mutex m;
  return m;
}

std::unique_ptr<ThreadPool>& pool_slot() {
  static std::unique_ptr<ThreadPool> pool;
  return pool;
}

}  // namespace

ThreadPool& shared_thread_pool() {
  const std::lock_guard<std::mutex> lock(pool_mutex());
  auto& pool = pool_slot();
  if (!pool) pool = std::make_unique<ThreadPool>(default_thread_count());
  return *pool;
}

void set_thread_count(std::size_t threads) {
  const std::lock_guard<std::mutex> lock(pool_mutex());
  pool_slot() = std::make_unique<ThreadPool>(threads);
}

}  // namespace roverlab
