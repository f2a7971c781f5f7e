// The thread pool studies run their independent parts on (issue 46): every
// part runs once, nested calls finish, errors come back in index order, and
// the rover and single-wheel studies give bit-identical results on one
// thread and on several.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "core/common/thread_pool.h"
#include "core/discrepancy/rover/study.h"
#include "core/discrepancy/single_wheel/study.h"
#include "core/simulation/rocker_bogie.h"
#include "importers/soil_file.h"
#include "importers/wheel_test_csv.h"
#include "terramechanics_soils.h"
#include "tests/support/resampled_wheel_test.h"

using namespace roverlab;

namespace {

// The shared pool at `threads`, put back to the machine's afterwards.
struct Threads {
  explicit Threads(std::size_t n) { set_thread_count(n); }
  ~Threads() { set_thread_count(default_thread_count()); }
  Threads(const Threads&) = delete;
  Threads& operator=(const Threads&) = delete;
};

}  // namespace

TEST(ThreadPool, EveryPartRunsOnceAndNestedCallsFinish) {
  ThreadPool pool(3);
  EXPECT_EQ(pool.threads(), 3u);
  std::vector<std::atomic<int>> runs(64);
  std::atomic<int> other_threads{0};
  const auto caller = std::this_thread::get_id();
  pool.for_each_index(8, [&](std::size_t i) {
    if (std::this_thread::get_id() != caller) ++other_threads;
    pool.for_each_index(8, [&](std::size_t j) {
      ++runs[8 * i + j];
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    });
  });
  for (const auto& r : runs) EXPECT_EQ(r.load(), 1);
  EXPECT_GT(other_threads.load(), 0);  // the workers took part
  int alone = 0;
  ThreadPool(1).for_each_index(5, [&](std::size_t) { ++alone; });  // one thread: all on the caller
  EXPECT_EQ(alone, 5);
}

// A thread whose own parts have ended runs the parts another thread's part
// has put on the pool, instead of idling until that part ends (the slower of
// two fits sets a study's pace otherwise).
TEST(ThreadPool, AThreadWaitingForAPartHelpsWithThePartsItRunsOnThePool) {
  ThreadPool pool(2);
  std::atomic<int> inner{0};
  std::atomic<bool> worker_started{false};
  std::vector<std::thread::id> ran_by(16);
  const auto caller = std::this_thread::get_id();
  pool.for_each_index(2, [&](std::size_t) {
    if (std::this_thread::get_id() == caller) {  // the quick part, once the other has started on the worker
      while (!worker_started) std::this_thread::yield();
      return;
    }
    worker_started = true;
    pool.for_each_index(ran_by.size(), [&](std::size_t j) {
      ran_by[j] = std::this_thread::get_id();
      ++inner;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    });
  });
  EXPECT_EQ(inner.load(), 16);
  std::sort(ran_by.begin(), ran_by.end());
  EXPECT_EQ(std::unique(ran_by.begin(), ran_by.end()) - ran_by.begin(), 2)
      << "part 1's parts ran on one thread: the other idled";
  // The same beside run_beside: the foreground's thread helps the background's parts.
  std::vector<std::thread::id> beside(16);
  pool.run_beside(
      [&] {
        pool.for_each_index(beside.size(), [&](std::size_t j) {
          beside[j] = std::this_thread::get_id();
          std::this_thread::sleep_for(std::chrono::milliseconds(10));
        });
      },
      [] {});
  std::sort(beside.begin(), beside.end());
  EXPECT_EQ(std::unique(beside.begin(), beside.end()) - beside.begin(), 2);
}

TEST(ThreadPool, TheLowestFailingPartsErrorComesBackAfterAllHaveRun) {
  ThreadPool pool(2);
  std::atomic<int> ran{0};
  try {
    pool.for_each_index(10, [&](std::size_t i) {
      ++ran;
      if (i == 3 || i == 7) throw std::runtime_error("part " + std::to_string(i));
    });
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "part 3");
  }
  EXPECT_EQ(ran.load(), 10);
  std::atomic<bool> background{false};
  EXPECT_THROW(pool.run_beside([&] { background = true; }, [] { throw std::logic_error("foreground"); }),
               std::logic_error);
  EXPECT_TRUE(background.load());
}

TEST(ThreadPool, RoverlabThreadsLimitsThePoolAndAnythingElseIsRefused) {
  const char* was = std::getenv("ROVERLAB_THREADS");
  const std::string saved = was != nullptr ? was : "";
  setenv("ROVERLAB_THREADS", "1", 1);
  EXPECT_EQ(default_thread_count(), 1u);
  setenv("ROVERLAB_THREADS", "3", 1);
  EXPECT_EQ(default_thread_count(), 3u);
  for (const char* bad : {"0", "-2", "two", "2x"}) {
    setenv("ROVERLAB_THREADS", bad, 1);
    try {
      default_thread_count();
      ADD_FAILURE() << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("ROVERLAB_THREADS"), std::string::npos) << e.what();
    }
  }
  unsetenv("ROVERLAB_THREADS");
  EXPECT_EQ(default_thread_count(), std::max(1U, std::thread::hardware_concurrency()));
  if (was != nullptr) setenv("ROVERLAB_THREADS", saved.c_str(), 1);
}

namespace {

// NaN (a sigma a screen does not give) as a number EXPECT_EQ can compare.
double comparable(double x) { return std::isnan(x) ? 1e300 : x; }

// Every number a single-wheel report holds that the screen, the folds and the
// selection compute, in order.
std::vector<double> numbers(const analysis::DiscrepancyReport& r) {
  std::vector<double> v = {r.baseline_bic, r.baseline_score, static_cast<double>(r.best)};
  for (const auto* list : {&r.candidates, &r.selection}) {
    for (const auto& c : *list) {
      v.insert(v.end(), {c.bic, c.delta_bic, c.held_out_score, c.fit.chi2});
      for (const auto& p : c.fit.parameters) v.insert(v.end(), {p.value, p.sigma});
      v.insert(v.end(), c.held_out_rmse.begin(), c.held_out_rmse.end());
    }
  }
  for (double& x : v) x = std::isnan(x) ? 1e300 : x;  // NaN as a number EXPECT_EQ can compare
  return v;
}

}  // namespace

TEST(ThreadPool, TheSingleWheelStudyIsTheSameOnOneThreadAndOnThree) {
  auto points = test::resampled_wheel_test(
      io::read_wheel_test_csv(std::string(ROVERLAB_TEST_DATA) + "/single_wheel/ding2011_tyii.csv"), 120);
  analysis::DiscrepancyReport one, three;
  {
    const Threads t(1);
    one = analysis::study_single_wheel(test::ding_tyii(), points);
  }
  {
    const Threads t(3);
    three = analysis::study_single_wheel(test::ding_tyii(), points);
  }
  ASSERT_FALSE(one.candidates.empty());
  EXPECT_EQ(numbers(one), numbers(three));
  EXPECT_EQ(one.verdict, three.verdict);
  EXPECT_EQ(one.final_model, three.final_model);
  // At a slip angle the two readings of slip run side by side.
  points.resize(24);
  for (auto& p : points) p.slip_angle = 0.1745;  // 10 deg: the readings differ by more than 0.01 in slip
  {
    const Threads t(1);
    one = analysis::study_single_wheel(test::ding_tyii(), points);
  }
  {
    const Threads t(3);
    three = analysis::study_single_wheel(test::ding_tyii(), points);
  }
  EXPECT_EQ(numbers(one), numbers(three));
  EXPECT_EQ(one.slip_definition, three.slip_definition);
  EXPECT_EQ(one.slip_definition_reason, three.slip_definition_reason);
  EXPECT_EQ(one.verdict, three.verdict);
}

// A fit's points are evaluated in chunks on the pool (soil_identification.cpp,
// PointEvaluations): the same fit, bit for bit, on one thread and on three,
// by autodiff (Wong-Reece) and by numeric differences (RFT at a slip angle).
TEST(ThreadPool, AFitIsTheSameOnOneThreadAndOnThree) {
  auto points = test::resampled_wheel_test(
      io::read_wheel_test_csv(std::string(ROVERLAB_TEST_DATA) + "/single_wheel/ding2011_tyii.csv"), 200);
  for (const terramechanics::ModelKind kind : {terramechanics::ModelKind::wong_reece, terramechanics::ModelKind::rft}) {
    terramechanics::IdentificationOptions io;
    io.model.kind = kind;
    io.free = kind == terramechanics::ModelKind::rft
                  ? std::vector<terramechanics::Parameter>{terramechanics::Parameter::rft_scale}
                  : std::vector<terramechanics::Parameter>{terramechanics::Parameter::n,
                                                           terramechanics::Parameter::friction_angle};
    if (kind == terramechanics::ModelKind::rft) {
      for (auto& p : points) p.slip_angle = 0.2;
    }
    terramechanics::IdentificationResult one, three;
    {
      const Threads t(1);
      one = terramechanics::identify_soil(test::ding_tyii(), points, io);
    }
    {
      const Threads t(3);
      three = terramechanics::identify_soil(test::ding_tyii(), points, io);
    }
    ASSERT_EQ(one.parameters.size(), io.free.size());
    ASSERT_EQ(three.parameters.size(), io.free.size());
    for (std::size_t i = 0; i < io.free.size(); ++i) {
      EXPECT_EQ(one.parameters[i].value, three.parameters[i].value);
      EXPECT_EQ(comparable(one.parameters[i].sigma), comparable(three.parameters[i].sigma));
    }
    ASSERT_EQ(one.residuals.size(), three.residuals.size());
    for (std::size_t i = 0; i < one.residuals.size(); ++i)
      EXPECT_EQ(comparable(one.residuals[i].predicted), comparable(three.residuals[i].predicted));
    EXPECT_TRUE(one.converged) << one.message;
  }
}

// The family step: the two families' baselines side by side, their folds in
// parallel, then each family's study (on a long file the second one's on a
// random subset first).
TEST(ThreadPool, TheFamilyStepIsTheSameOnOneThreadAndOnThree) {
  const auto points = test::resampled_wheel_test(
      io::read_wheel_test_csv(std::string(ROVERLAB_TEST_DATA) + "/single_wheel/ding2011_tyii.csv"), 60);
  for (const std::size_t screen : {std::size_t{0}, std::size_t{30}}) {
    analysis::DiscrepancyOptions o;
    o.compare_families = true;
    o.family_screen_points = screen;
    analysis::DiscrepancyReport one, three;
    {
      const Threads t(1);
      one = analysis::study_single_wheel(test::ding_tyii(), points, o);
    }
    {
      const Threads t(3);
      three = analysis::study_single_wheel(test::ding_tyii(), points, o);
    }
    EXPECT_EQ(numbers(one), numbers(three));
    EXPECT_EQ(one.family_choice, three.family_choice);
    EXPECT_EQ(one.verdict, three.verdict);
    ASSERT_EQ(one.families.size(), 2u);
    ASSERT_EQ(three.families.size(), 2u);
    for (std::size_t k = 0; k < 2; ++k) {
      const auto &a = one.families[k], &b = three.families[k];
      EXPECT_EQ(a.family, b.family);
      EXPECT_EQ(a.held_out_score, b.held_out_score);
      EXPECT_EQ(a.held_out_rmse, b.held_out_rmse);
      EXPECT_EQ(comparable(a.final_held_out_score), comparable(b.final_held_out_score));
      EXPECT_EQ(a.final_model, b.final_model);
      EXPECT_EQ(a.studied_points, b.studied_points);
    }
    // Both families were studied (the first's final model is not within the noise here).
    EXPECT_FALSE(one.families[0].final_model.empty()) << one.family_choice;
    EXPECT_FALSE(one.families[1].final_model.empty()) << one.family_choice;
  }
}

namespace {

std::vector<double> numbers(const analysis::RoverDiscrepancyReport& r) {
  std::vector<double> v = {r.baseline_bic, r.baseline_held_out, r.final_held_out, static_cast<double>(r.simulations)};
  for (const auto& c : r.candidates) {
    v.insert(v.end(), {c.minus_two_log_l, c.delta_bic, c.held_out, static_cast<double>(c.simulations)});
    for (const auto& p : c.parameters) v.insert(v.end(), {p.value, comparable(p.sigma)});
  }
  for (const auto& s : r.selection) {
    v.insert(v.end(), {s.delta_bic, s.held_out});
    for (const auto& p : s.parameters) v.insert(v.end(), {p.value, comparable(p.sigma)});
  }
  return v;
}

}  // namespace

TEST(ThreadPool, TheRoverStudyIsTheSameOnOneThreadAndOnThree) {
  analysis::RoverScenarioModel m;
  m.name = "flat test";
  m.rover = "kapvik_planar";
  m.run.soil = io::load_soil(std::string(ROVERLAB_RESOURCES_DIR) + "/soils/ding_tyii.json");
  m.run.path = simulation::flat_path();
  m.run.duration = 20;
  simulation::RockerBogieRun run = m.run;
  run.seed = 5;
  simulation::set_effect(run.effects, "slip-sinkage", 0.3);
  simulation::set_effect(run.effects, "force-offset", 0.4);
  const log::Log lg = simulation::simulate_rocker_bogie(m.geometry, m.parameters, run).log;
  analysis::RoverDiscrepancyReport one, three;
  {
    const Threads t(1);
    one = analysis::study_rover(lg, m);
  }
  {
    const Threads t(3);
    three = analysis::study_rover(lg, m);
  }
  ASSERT_FALSE(one.candidates.empty());
  ASSERT_FALSE(one.selection.empty());  // a round with fits, not screens alone
  EXPECT_EQ(numbers(one), numbers(three));
  EXPECT_EQ(one.verdict, three.verdict);
  EXPECT_EQ(one.dropped, three.dropped);
}
