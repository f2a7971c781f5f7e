#pragma once
// Estimators that survive and say so (issue 17): the pieces both the
// contact-angle and the INS slip estimators use. The IMU's samples are the
// process model's inputs, not measurements, so they are screened before a
// filter sees them: a sample outside the sensor's physical range or far from
// its neighbours (a Hampel test) is rejected, a non-finite one is missing, and
// the filter bridges both by prediction from the last usable sample; runs of
// them, and time stamps too far apart, are reported as gaps (longer than
// max_bridged_gap: refused). Measurement updates are gated by their
// normalised innovation squared (NIS) against its chi-square bound, and a
// monitor watches each filter's health (covariance finite and positive
// definite, states finite and within physical bounds, updates not gated
// away for long) and says when to reset it. What was rejected, bridged and
// reset is a HealthReport, which the results carry and state in words.

#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace roverlab::estimation {

// Quantile of the chi-square distribution with `dof` degrees of freedom
// (Wilson-Hilferty approximation; within 1 % for dof >= 2 at p <= 1 - 1e-9).
double chi_square_quantile(double dof, double probability);

struct TimeGap {
  double start = 0, end = 0;  // s: the last usable sample before, the first after
};

struct ImuScreenOptions {
  // Physical range: a MEMS IMU's full scale (2000 deg/s, 16 g). Beyond it a
  // sample cannot be a measurement.
  double max_angular_rate = 35.0;     // rad/s, per axis
  double max_specific_force = 160.0;  // m/s^2, per axis
  // Hampel test: a sample further from the median of its 2 half_window + 1
  // neighbours than hampel_k robust standard deviations (1.4826 MAD) plus a
  // floor is an outlier. The floors are larger than any change a rover's
  // motion makes within a few samples.
  int half_window = 5;
  double hampel_k = 8.0;
  double min_rate_jump = 2.0;    // rad/s
  double min_force_jump = 30.0;  // m/s^2
  // Longest time without a usable sample that prediction bridges, s; an
  // interval longer than gap_periods nominal sample periods is a gap.
  double max_bridged_gap = 1.0;
  double gap_periods = 3.0;
};

// The IMU as the filters see it: channels angular_rate_x..z then
// specific_force_x..z, every rejected or missing sample replaced by the last
// usable one (the first usable one before it), with what was done.
struct ScreenedImu {
  std::array<std::vector<double>, 6> values;
  std::vector<char> bridged;  // 1 where the sample was rejected or missing
  std::size_t outliers = 0;   // finite samples rejected
  std::size_t missing = 0;    // non-finite samples
  std::vector<TimeGap> gaps;
  // A run of bridged samples [begin, end) and the robust spread (1.4826 MAD)
  // of each channel's usable samples either side: how far the bridge may be
  // from what the IMU measured.
  struct Run {
    std::size_t begin = 0, end = 0;
    std::array<double, 6> spread{};
  };
  std::vector<Run> runs;
  // The process noise a filter adds for the bridged input at sample i, per
  // channel, in the input's units squared (0 when i is not bridged): the
  // bridge's error is correlated along a run, so its variance after k
  // samples is (k spread)^2 and each step adds (2k - 1) spread^2.
  double added_variance(std::size_t i, int channel) const;
};

// Screens an IMU stream's six channels. Throws DataError naming the stream
// when a gap is longer than max_bridged_gap ("a gap of ...") or no sample is
// usable.
ScreenedImu screen_imu(const std::string& stream, const std::vector<double>& time,
                       const std::array<const std::vector<double>*, 6>& rate_then_force,
                       const ImuScreenOptions& options);

struct HealthOptions {
  // NIS gate: an update whose NIS exceeds the chi-square quantile of this
  // probability is rejected (state and covariance left as predicted).
  double gate_probability = 1.0 - 1e-9;
  // Gated updates back to back for this long mean the filter has lost the
  // measurements (diverged), s.
  double max_rejected_time = 1.0;
  // After a reset, samples are invalid for this long while it re-converges, s.
  double recovery_time = 1.0;
  // Resets allowed; after the last one the filter stops (samples invalid).
  int max_resets = 5;
  // NIS moving average over this long is compared with its band, s.
  double nis_window = 2.0;
  // The whole covariance's finiteness and positive definiteness (a Cholesky
  // factorisation) at most this often, s; the state's finiteness and bounds
  // and P's diagonal are checked at every step.
  double factorisation_interval = 0.1;
};

enum class HealthStatus { ok, degraded, diverged };
const char* to_string(HealthStatus status);

// What a run's filters rejected, bridged and reset.
struct HealthReport {
  std::size_t outliers_rejected = 0;     // IMU samples outside the range or the Hampel test
  std::size_t missing_samples = 0;       // non-finite IMU samples
  std::size_t measurements_missing = 0;  // steps without a finite measurement sample: predicted only
  std::size_t updates_rejected = 0;      // measurement updates gated by NIS
  std::size_t updates = 0;               // measurement updates offered to the gate
  std::vector<TimeGap> gaps;             // bridged by prediction
  std::size_t resets = 0;
  bool stopped = false;         // resets exhausted: the rest is invalid
  double invalid_fraction = 0;  // samples marked invalid for divergence
  // The first divergence, s, and why; after merge_reversed, the forward
  // pass's when it diverged, else the reversed pass's first (in the log's
  // clock, its latest), with the reversed pass's named in the reason.
  double divergence_time = NAN;
  std::string divergence_reason;
  double nis_out_of_band_fraction = 0;  // share of NIS windows above their band
  // ok: nothing rejected, bridged or reset; degraded: inputs or updates
  // rejected or gaps bridged; diverged: a filter was reset or stopped.
  HealthStatus status() const;
  // One line in words, e.g. "3 IMU samples rejected as outliers; 1 gap of
  // 0.10 s bridged by prediction".
  std::string message() const;
  // Adds another pass's counts (the INS runs two filters over one log).
  void merge(const HealthReport& other);
  // Adds a pass over the log reversed in time (t' = mirror - t) whose
  // estimates are fused with this pass's (the two-filter smoother): its gated
  // updates and resets, its divergence in the log's clock with a reason that
  // names it with its count of resets. `resets` is then both passes' sum;
  // where the reversed pass diverged the fused states are this pass's, so
  // the invalid fraction and `stopped` stay this pass's.
  void merge_reversed(const HealthReport& reversed, double mirror);
};

// Watches one filter pass. The estimator offers each update's NIS to
// record() (after gating it by gate()), calls check() after each step and, when it returns a reason,
// resets its filter and calls reset() (or stops when reset() says so).
class FilterHealthMonitor {
 public:
  explicit FilterHealthMonitor(const HealthOptions& options = {}) : o_(options) {}
  // The NIS gate of an update of `dof` measurements (a chi-square quantile).
  double gate(int dof);
  // Records an update's NIS: into the moving average, and, when `gated`,
  // as rejected when above gate(dof).
  void record(double t, double nis, int dof, bool gated = true);
  // Empty when healthy, else why not: covariance not finite or not positive
  // definite (LLT), state not finite or outside [lower, upper] (entries
  // where a bound is NaN are not checked; named by `names` when given),
  // updates gated for too long.
  std::string check(double t, const Eigen::Ref<const Eigen::MatrixXd>& P, const Eigen::Ref<const Eigen::VectorXd>& x,
                    const Eigen::Ref<const Eigen::VectorXd>& lower, const Eigen::Ref<const Eigen::VectorXd>& upper,
                    const std::vector<std::string>& names = {});
  // Records a divergence at t; false when the resets are exhausted (stop).
  bool reset(double t, const std::string& reason);
  // Samples at t are invalid: recovering from a reset, or stopped.
  bool invalid_at(double t) const;
  bool stopped() const { return report_.stopped; }
  HealthReport& report() { return report_; }
  const HealthReport& report() const { return report_; }

 private:
  HealthOptions o_;
  HealthReport report_;
  std::vector<double> gates_;    // by dof
  double rejected_since_ = NAN;  // first of the current run of gated updates
  double last_reset_ = NAN;
  double last_factorisation_ = NAN;
  // NIS moving average: sum of NIS / dof over the current window.
  double window_start_ = NAN, window_sum_ = 0, window_dof_ = 0;
  std::size_t windows_ = 0, windows_out_ = 0;
};

}  // namespace roverlab::estimation
