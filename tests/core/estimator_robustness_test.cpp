// Issue 17 item 4, "estimators that survive and say so": IMU outliers, a
// 0.1 s dropout, one absurd sample and a long stretch of absurd data, injected
// into logs other than those the estimators' own tests use, for the
// contact-angle EKF and UKF (seed 000) and the INS slip estimator (seed 002).
// The figures are in docs/validation/estimator-robustness.md.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <numeric>
#include <ostream>
#include <string>

#include "core/estimation/contact_angle/contact_angle.h"
#include "core/estimation/ins_slip/ins_slip.h"
#include "core/filters/filter_health.h"
#include "core/simulation/flying_rover.h"
#include "core/simulation/skid_steer_scenario.h"
#include "importers/mapping.h"
#include "importers/matlab_importer.h"
#include "importers/rover_file.h"

using namespace roverlab;

namespace {

const kinematics::RoverModel& bb2() {
  static const kinematics::RoverModel m =
      *io::load_rover(std::string(ROVERLAB_RESOURCES_DIR) + "/rovers/exomars_bb2.json").dh;
  return m;
}

// The log with the IMU's channels edited: edit(channel name, values, time).
using ImuEdit = std::function<void(const std::string&, std::vector<double>&, const std::vector<double>&)>;
log::Log with_imu(const log::Log& lg, const ImuEdit& edit) {
  log::Log out;
  out.metadata = lg.metadata;
  for (const log::Stream& s : lg.streams()) {
    if (s.name() != "imu") {
      out.add_stream(s);
      continue;
    }
    log::Stream imu(s.name(), s.time());
    for (const log::Channel& c : s.channels()) {
      std::vector<double> v = c.values;
      edit(c.name, v, s.time());
      imu.add_channel(c.name, c.unit, std::move(v), c.description);
    }
    out.add_stream(std::move(imu));
  }
  return out;
}

// Three outliers as the robustness probe found them: +40 rad/s and -35 rad/s
// on two gyro axes, 400 m/s^2 on an accelerometer axis, at 30, 50 and 70 % of the log.
log::Log with_three_outliers(const log::Log& lg) {
  return with_imu(lg, [](const std::string& c, std::vector<double>& v, const std::vector<double>&) {
    const std::size_t n = v.size();
    if (c == "angular_rate_x") v[3 * n / 10] = 40.0;
    if (c == "angular_rate_z") v[5 * n / 10] = -35.0;
    if (c == "specific_force_z") v[7 * n / 10] = 400.0;
  });
}

// Every IMU channel NaN for `seconds` from `at` (a fraction) of the log.
log::Log with_dropout(const log::Log& lg, double seconds, double at = 0.5) {
  return with_imu(lg, [seconds, at](const std::string&, std::vector<double>& v, const std::vector<double>& t) {
    const double t0 = t[static_cast<std::size_t>(at * static_cast<double>(t.size()))];
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (t[i] >= t0 && t[i] < t0 + seconds) v[i] = NAN;
    }
  });
}

log::Log with_one_sample(const log::Log& lg, const char* channel, double value) {
  return with_imu(lg, [channel, value](const std::string& c, std::vector<double>& v, const std::vector<double>&) {
    if (c == channel) v[2 * v.size() / 5] = value;
  });
}

// A channel stuck at `value` for `seconds` from 40 % of the log: within the
// sensor's range and smooth, so no sample test can reject it.
log::Log with_stuck(const log::Log& lg, const char* channel, double value, double seconds) {
  return with_imu(lg, [=](const std::string& c, std::vector<double>& v, const std::vector<double>& t) {
    const double t0 = t[2 * t.size() / 5];
    if (c != channel) return;
    for (std::size_t i = 0; i < v.size(); ++i) {
      if (t[i] >= t0 && t[i] < t0 + seconds) v[i] = value;
    }
  });
}

double relative_change(double value, double reference) { return std::abs(value - reference) / reference; }

// --- contact angles -----------------------------------------------------

log::Log flying_rover_log(const std::string& scenario, unsigned seed, double rate) {
  auto s = simulation::flying_rover_scenario(scenario, bb2());
  s.seed = seed;
  s.rate = rate;
  return simulation::simulate_flying_rover(bb2(), s);
}

estimation::ContactAngleOptions contact_options(estimation::FilterKind filter, bool smoother) {
  estimation::ContactAngleOptions o;
  o.model = estimation::ContactModel::contact;
  o.filter = filter;
  o.reset_cross_covariance = true;
  o.smoother = smoother;  // the two-filter smoother, --smoother's default
  return o;
}

// Mean over the six wheels of the contact angle's RMS error, deg.
double mean_contact_rms_deg(const estimation::ContactAngleResult& r) {
  double sum = 0;
  for (double e : r.rms.contact_angle) sum += e;
  return sum / static_cast<double>(r.rms.contact_angle.size()) * 180.0 / M_PI;
}

struct ContactCase {
  const char* name;
  estimation::FilterKind filter;
  const char* scenario;
  unsigned seed;
  double rate;
  bool smoother = false;
};
// Test names show the case's name, not its bytes.
void PrintTo(const ContactCase& c, std::ostream* os) { *os << c.name; }

class ContactAngleRobustness : public ::testing::TestWithParam<ContactCase> {
 protected:
  estimation::ContactAngleResult run(const log::Log& lg) const {
    return estimation::run_contact_angle(lg, bb2(), contact_options(GetParam().filter, GetParam().smoother));
  }
  const log::Log& clean() const {
    static std::map<std::string, log::Log> logs;
    const ContactCase& c = GetParam();
    auto it = logs.find(c.name);
    if (it == logs.end()) it = logs.emplace(c.name, flying_rover_log(c.scenario, c.seed, c.rate)).first;
    return it->second;
  }
};

TEST_P(ContactAngleRobustness, ThreeImuOutliersChangeTheRmsErrorByUnderTenPercentAndAreCounted) {
  const auto clean_run = run(clean());
  const auto dirty = run(with_three_outliers(clean()));
  const double a = mean_contact_rms_deg(clean_run), b = mean_contact_rms_deg(dirty);
  std::printf("[figures] %s clean %.3f deg, three outliers %.3f deg\n  clean: %s\n  outliers: %s\n", GetParam().name, a,
              b, clean_run.health.message().c_str(), dirty.health.message().c_str());
  EXPECT_EQ(clean_run.health.status(), estimation::HealthStatus::ok) << clean_run.health.message();
  EXPECT_LT(relative_change(b, a), 0.10) << a << " " << b;
  EXPECT_EQ(dirty.health.outliers_rejected, 3u);
  EXPECT_EQ(dirty.health.status(), estimation::HealthStatus::degraded);
  EXPECT_NE(dirty.health.message().find("3 IMU samples rejected as outliers"), std::string::npos)
      << dirty.health.message();
}

TEST_P(ContactAngleRobustness, ATenthOfASecondDropoutIsBridgedByPredictionAndReportedAsAGap) {
  const auto clean_run = run(clean());
  const auto dropped = run(with_dropout(clean(), 0.1));
  const double a = mean_contact_rms_deg(clean_run), b = mean_contact_rms_deg(dropped);
  std::printf("[figures] %s clean %.3f deg, 0.1 s dropout %.3f deg\n  dropout: %s\n", GetParam().name, a, b,
              dropped.health.message().c_str());
  EXPECT_LT(relative_change(b, a), 0.20) << a << " " << b;
  ASSERT_EQ(dropped.health.gaps.size(), 1u);
  const double period = 1.0 / GetParam().rate;
  EXPECT_NEAR(dropped.health.gaps[0].end - dropped.health.gaps[0].start, 0.1 + period, 1.5 * period);
  EXPECT_NEAR(static_cast<double>(dropped.health.missing_samples), 0.1 * GetParam().rate, 1.0);
  EXPECT_NE(dropped.health.message().find("1 gap of 0.1"), std::string::npos) << dropped.health.message();
  // The bridged samples are estimates (predictions), flagged as such.
  const auto& bridged = dropped.estimates.stream("estimate/contact/wheels").channel("bridged").values;
  EXPECT_NEAR(std::accumulate(bridged.begin(), bridged.end(), 0.0), 0.1 * GetParam().rate, 1.0);
}

TEST_P(ContactAngleRobustness, OneAbsurdSampleNeverEntersThePrediction) {
  const auto clean_run = run(clean());
  const auto absurd = run(with_one_sample(clean(), "angular_rate_y", 1e6));
  const double a = mean_contact_rms_deg(clean_run), b = mean_contact_rms_deg(absurd);
  std::printf("[figures] %s clean %.3f deg, one 1e6 rad/s sample %.3f deg\n  absurd: %s\n", GetParam().name, a, b,
              absurd.health.message().c_str());
  EXPECT_LT(relative_change(b, a), 0.10) << a << " " << b;
  EXPECT_EQ(absurd.health.outliers_rejected, 1u);
  EXPECT_EQ(absurd.health.resets, 0u);
}

TEST_P(ContactAngleRobustness, AStuckGyroOverSecondsIsReportedAsDivergenceNotSilently) {
  const auto stuck = run(with_stuck(clean(), "angular_rate_z", 20.0, 4.0));
  std::printf("[figures] %s stuck gyro: %s\n", GetParam().name, stuck.health.message().c_str());
  EXPECT_EQ(stuck.health.status(), estimation::HealthStatus::diverged) << stuck.health.message();
  EXPECT_GE(stuck.health.resets, 1u);
  EXPECT_GT(stuck.health.invalid_fraction, 0.0);
  EXPECT_NE(stuck.health.message().find("diverged at t = "), std::string::npos);
  // The samples where it diverged are invalid in the streams, and the filter
  // recovers once the gyro does: the last 5 s are valid.
  const auto& s = stuck.estimates.stream("estimate/contact/wheels");
  const auto& valid = s.channel("valid").values;
  EXPECT_GT(std::count(valid.begin(), valid.end(), 0.0), 0);
  const std::size_t n = valid.size();
  EXPECT_EQ(std::count(valid.end() - static_cast<std::ptrdiff_t>(n / 6), valid.end(), 0.0), 0);
  EXPECT_TRUE(std::isfinite(s.channel("contact_angle_FL").values.back()));
  if (!GetParam().smoother) return;
  // The backward pass meets the stuck gyro too: its resets are counted and
  // named, in the log's clock, beside the forward filter's.
  auto o = contact_options(GetParam().filter, false);
  const auto forward = estimation::run_contact_angle(with_stuck(clean(), "angular_rate_z", 20.0, 4.0), bb2(), o);
  EXPECT_GT(stuck.health.resets, forward.health.resets) << stuck.health.message();
  EXPECT_EQ(stuck.health.invalid_fraction, forward.health.invalid_fraction);
  EXPECT_EQ(stuck.filter_health.resets, forward.health.resets);
  EXPECT_EQ(stuck.health.divergence_time, forward.health.divergence_time);
  // The backward pass's first divergence, in the log's clock, lies within
  // the stuck stretch [t0, t0 + 4 s): it meets the stretch's end first.
  const std::string m = stuck.health.message();
  const std::size_t at = m.find("backward pass, ");
  ASSERT_NE(at, std::string::npos) << m;
  const std::size_t from = m.find("from t = ", at);
  ASSERT_NE(from, std::string::npos) << m;
  const double tb = std::stod(m.substr(from + 9));
  const auto& t = clean().stream("imu").time();
  const double t0 = t[2 * t.size() / 5];
  EXPECT_GT(tb, t0) << m;
  EXPECT_LT(tb, t0 + 4.0) << m;
}

INSTANTIATE_TEST_SUITE_P(
    EkfAndUkf, ContactAngleRobustness,
    ::testing::Values(
        ContactCase{"ekf_bump_crossing_seed3", estimation::FilterKind::ekf, "bump-crossing", 3, 100.0},
        ContactCase{"ukf_rear_bogie_seed5", estimation::FilterKind::ukf, "rear-bogie-rotation", 5, 50.0},
        // The smoother runs the filter over the log reversed in time too:
        // the same screening must hold in both passes and in their fusion.
        ContactCase{"ekf_smoother_fl_bogie_seed4", estimation::FilterKind::ekf, "fl-bogie-rotation", 4, 200.0, true},
        ContactCase{"ukf_smoother_bump_crossing_seed7", estimation::FilterKind::ukf, "bump-crossing", 7, 50.0, true}),
    [](const ::testing::TestParamInfo<ContactCase>& info) { return std::string(info.param.name); });

// --- INS slip ------------------------------------------------------------

struct InsCase {
  const char* name;
  std::function<log::Log()> make;
};
void PrintTo(const InsCase& c, std::ostream* os) { *os << c.name; }

log::Log pathfinder_log() {
  return io::read_mapped_hdf5(std::string(ROVERLAB_TEST_DATA) + "/test17run.mat",
                              io::load_mapping(std::string(ROVERLAB_RESOURCES_DIR) + "/mappings/wvu_pathfinder.json"));
}

class InsRobustness : public ::testing::TestWithParam<InsCase> {
 protected:
  static estimation::InsSlipResult run(const log::Log& lg) { return estimation::run_ins_slip(lg, {}); }
  const log::Log& clean() const {
    static std::map<std::string, log::Log> logs;
    auto it = logs.find(GetParam().name);
    if (it == logs.end()) it = logs.emplace(GetParam().name, GetParam().make()).first;
    return it->second;
  }
};

TEST_P(InsRobustness, ThreeImuOutliersChangeThePositionRmseByUnderTenPercentAndAreCounted) {
  const auto clean_run = run(clean());
  const auto dirty = run(with_three_outliers(clean()));
  const double a = clean_run.metrics.position_rmse, b = dirty.metrics.position_rmse;
  std::printf("[figures] %s clean %.3f m, three outliers %.3f m\n  clean: %s\n  outliers: %s\n", GetParam().name, a, b,
              clean_run.health.message().c_str(), dirty.health.message().c_str());
  EXPECT_LT(relative_change(b, a), 0.10) << a << " " << b;
  EXPECT_EQ(dirty.health.outliers_rejected, 3u);
  EXPECT_NE(dirty.health.message().find("3 IMU samples rejected as outliers"), std::string::npos)
      << dirty.health.message();
  EXPECT_NE(dirty.health.status(), estimation::HealthStatus::diverged);
}

// The dropout at five places: the position RMSE changes by under 20 % either
// way. On the Pathfinder log it used to improve by up to 43 % (the bridge's
// process noise let the updates correct an attitude the clean pass held too
// confidently); with the initial heading aligned to the GPS track (issue 14)
// that attitude error no longer turns into a heading error over the whole
// run (docs/validation/estimator-robustness.md).
TEST_P(InsRobustness, ATenthOfASecondDropoutIsBridgedByPredictionAndReportedAsAGap) {
  const auto clean_run = run(clean());
  const double a = clean_run.metrics.position_rmse;
  for (double at : {0.3, 0.4, 0.5, 0.6, 0.7}) {
    const auto dropped = run(with_dropout(clean(), 0.1, at));
    const double b = dropped.metrics.position_rmse;
    std::printf("[figures] %s clean %.3f m, 0.1 s dropout at %.0f %% %.3f m\n  dropout: %s\n", GetParam().name, a,
                100 * at, b, dropped.health.message().c_str());
    EXPECT_LT(relative_change(b, a), 0.20) << at;
    ASSERT_EQ(dropped.health.gaps.size(), 1u);
    EXPECT_NEAR(dropped.health.gaps[0].end - dropped.health.gaps[0].start, 0.1, 0.02);
    EXPECT_NE(dropped.health.message().find("1 gap of 0.1"), std::string::npos) << dropped.health.message();
  }
}

TEST_P(InsRobustness, OneAbsurdSampleNeverEntersTheMechanisation) {
  const auto clean_run = run(clean());
  const auto absurd = run(with_one_sample(clean(), "angular_rate_z", 1e6));
  const double a = clean_run.metrics.position_rmse, b = absurd.metrics.position_rmse;
  std::printf("[figures] %s clean %.3f m, one 1e6 rad/s sample %.3f m\n", GetParam().name, a, b);
  EXPECT_LT(relative_change(b, a), 0.10) << a << " " << b;
  EXPECT_EQ(absurd.health.outliers_rejected, 1u);
}

TEST_P(InsRobustness, AStuckAccelerometerOverSecondsIsReportedAsDivergenceNotSilently) {
  const auto stuck = run(with_stuck(clean(), "specific_force_x", 30.0, 4.0));
  std::printf("[figures] %s stuck accelerometer: %s\n", GetParam().name, stuck.health.message().c_str());
  EXPECT_EQ(stuck.health.status(), estimation::HealthStatus::diverged) << stuck.health.message();
  EXPECT_GE(stuck.health.resets, 1u);
  EXPECT_GT(stuck.health.invalid_fraction, 0.0);
  const auto& valid = stuck.estimates.stream("estimate/ins/pose").channel("valid").values;
  EXPECT_GT(std::count(valid.begin(), valid.end(), 0.0), 0);
}

INSTANTIATE_TEST_SUITE_P(
    SimulatedAndPathfinder, InsRobustness,
    ::testing::Values(InsCase{"skid_steer_seed6",
                              [] { return simulation::simulate_skid_steer(simulation::default_slip_scenario(6)); }},
                      InsCase{"pathfinder_test17run", pathfinder_log}),
    [](const ::testing::TestParamInfo<InsCase>& info) { return std::string(info.param.name); });

// --- the pieces ------------------------------------------------------------

TEST(FilterHealth, ChiSquareQuantilesMatchTheTables) {
  EXPECT_NEAR(estimation::chi_square_quantile(18, 0.99), 34.805, 0.1);
  EXPECT_NEAR(estimation::chi_square_quantile(2, 0.999), 13.816, 0.3);
  EXPECT_NEAR(estimation::chi_square_quantile(3, 0.95), 7.815, 0.05);
}

TEST(FilterHealth, AGapLongerThanTheLongestBridgedIsStillRefused) {
  const log::Log lg = flying_rover_log("bump-crossing", 3, 50.0);
  try {
    estimation::run_contact_angle(with_dropout(lg, 1.5), bb2(), contact_options(estimation::FilterKind::ekf, false));
    FAIL() << "a 1.5 s dropout was bridged";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("a gap of"), std::string::npos) << e.what();
  }
}

// The two-filter smoother's report: a reversed pass's divergence at t' is
// at mirror - t' in the log's clock and named; the fused samples there are
// the forward pass's, so its invalid fraction and `stopped` do not carry over.
TEST(FilterHealth, AReversedPassIsMergedInTheLogsClock) {
  estimation::HealthReport backward;
  backward.updates = 100;
  backward.updates_rejected = 7;
  backward.resets = 2;
  backward.divergence_time = 3.0;
  backward.divergence_reason = "every update rejected by the NIS gate for 1 s";
  backward.invalid_fraction = 0.2;

  estimation::HealthReport clean;  // the forward pass did not diverge
  clean.updates = 100;
  clean.merge_reversed(backward, 10.0);
  EXPECT_EQ(clean.updates, 200u);
  EXPECT_EQ(clean.updates_rejected, 7u);
  EXPECT_EQ(clean.resets, 2u);
  EXPECT_DOUBLE_EQ(clean.divergence_time, 7.0);
  EXPECT_EQ(clean.divergence_reason, "backward pass, 2 resets: every update rejected by the NIS gate for 1 s");
  EXPECT_EQ(clean.invalid_fraction, 0.0);
  EXPECT_EQ(clean.status(), estimation::HealthStatus::diverged);

  estimation::HealthReport diverged;  // both did: the forward pass's time stays
  diverged.resets = 1;
  diverged.divergence_time = 2.0;
  diverged.divergence_reason = "covariance not finite";
  diverged.merge_reversed(backward, 10.0);
  EXPECT_EQ(diverged.resets, 3u);
  EXPECT_DOUBLE_EQ(diverged.divergence_time, 2.0);
  EXPECT_EQ(diverged.divergence_reason,
            "covariance not finite; backward pass, 2 resets, from t = 7.00 s: "
            "every update rejected by the NIS gate for 1 s");

  backward.stopped = true;  // the reversed pass stopped: the forward one did not
  estimation::HealthReport forward;
  forward.merge_reversed(backward, 10.0);
  EXPECT_FALSE(forward.stopped);
  EXPECT_NE(forward.message().find("then stopped (the forward filter's states kept"), std::string::npos)
      << forward.message();

  estimation::HealthReport quiet;  // a reversed pass without divergence adds its updates only
  estimation::HealthReport calm;
  calm.updates = 5;
  quiet.merge_reversed(calm, 10.0);
  EXPECT_EQ(quiet.updates, 5u);
  EXPECT_EQ(quiet.status(), estimation::HealthStatus::ok);
  EXPECT_TRUE(std::isnan(quiet.divergence_time));
}

TEST(FilterHealth, TheMonitorSeesACovarianceThatIsNotPositiveDefinite) {
  estimation::FilterHealthMonitor m;
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(2), none = Eigen::VectorXd::Constant(2, NAN);
  Eigen::MatrixXd P = Eigen::MatrixXd::Identity(2, 2);
  EXPECT_EQ(m.check(0.0, P, x, none, none), "");
  P(0, 1) = P(1, 0) = 2.0;  // finite, symmetric, eigenvalues 3 and -1
  EXPECT_EQ(m.check(1.0, P, x, none, none), "covariance not positive definite");
  P(0, 1) = P(1, 0) = NAN;
  EXPECT_EQ(m.check(2.0, P, x, none, none), "covariance not finite");
  const Eigen::VectorXd lower = Eigen::VectorXd::Constant(2, -1.0), upper = Eigen::VectorXd::Constant(2, 1.0);
  EXPECT_EQ(m.check(3.0, Eigen::MatrixXd::Identity(2, 2), Eigen::VectorXd::Constant(2, 2.0), lower, upper, {"a", "b"}),
            "a outside its physical bounds (2)");
  // Updates gated for longer than max_rejected_time (1 s) are a divergence too.
  for (double t = 4.0; t < 5.5; t += 0.1) m.record(t, 1e6, 3);
  EXPECT_NE(m.check(5.5, Eigen::MatrixXd::Identity(2, 2), x, none, none).find("rejected by the NIS gate"),
            std::string::npos);
  EXPECT_TRUE(m.reset(5.5, "test"));
  EXPECT_TRUE(m.invalid_at(6.0));
  EXPECT_FALSE(m.invalid_at(6.6));
}

}  // namespace
