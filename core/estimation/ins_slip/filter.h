#pragma once
// One pass of the INS slip estimator's error-state EKF (seed 002): strapdown
// mechanisation, covariance propagation, the pseudo-measurement and
// wheel-speed updates every update interval, and the optional
// Rauch-Tung-Striebel smoother over the update epochs.

#include <vector>

#include "core/estimation/ins_slip/ins_slip.h"
#include "core/estimation/ins_slip/models.h"

namespace roverlab::estimation {

// Local east-north-up frame at the reference's first fix.
struct LocalFrame {
  LocalFrame() = default;
  LocalFrame(double latitude, double longitude, double height);
  double latitude = 0, longitude = 0, height = 0;  // rad, rad, m
  double rn = 0, re = 0;                           // meridian and transverse radii plus height, m
};

// Filter outputs at the IMU samples.
struct InsTrack {
  InsTrack() = default;
  explicit InsTrack(std::size_t n);
  void record(std::size_t i, const InsState& s, const LocalFrame& frame);
  std::vector<double> roll, pitch, yaw, east, north, up, vn, ve, vd, vx, vy, vz;
  std::vector<std::vector<double>> bias;  // accel x y z, gyro x y z
  std::vector<double> valid;              // 0 where the filter had diverged (recovering or stopped)
  HealthReport health;                    // gated updates and divergences of the pass
};

// What every pass reads: IMU samples (body forward-right-down), wheel rates,
// the standstill flags and the initial pose.
struct InsPassInputs {
  using Samples = const std::vector<double>*;
  Samples time = nullptr;
  Samples fx = nullptr, fy = nullptr, fz = nullptr;  // specific force, m/s^2
  Samples wx = nullptr, wy = nullptr, wz = nullptr;  // angular rate, rad/s
  const log::Stream* wheels = nullptr;
  WheelSamples wheel_rates;
  std::vector<char> standstill;                // per IMU sample
  const ScreenedImu* screened = nullptr;       // what was bridged (the process noise it adds)
  double roll0 = 0, pitch0 = 0, heading0 = 0;  // rad
  double east0 = 0, north0 = 0;                // m, initial position in the local frame
  LocalFrame frame;

  std::size_t size() const { return time->size(); }
  Eigen::Vector3d force(std::size_t i) const { return {(*fx)[i], (*fy)[i], (*fz)[i]}; }
  Eigen::Vector3d rate(std::size_t i) const { return {(*wx)[i], (*wy)[i], (*wz)[i]}; }
  // Wheel sample nearest to t, clamped to the wheel-rate samples.
  std::size_t wheel_index(double t) const;
  // r omega, mean of the four wheels, at wheel-rate sample k.
  double wheel_speed(std::size_t k, double wheel_radius) const {
    return wheel_radius * 0.5 * (wheel_rates.left_rate[k] + wheel_rates.right_rate[k]);
  }
};

// One filter pass. `aiding` adds the wheels' forward speed as an update.
class InsFilterPass {
 public:
  InsFilterPass(const InsPassInputs& inputs, const InsSlipOptions& options, bool aiding);
  // Runs over every IMU sample; progress is reported from progress_base over
  // progress_share of the whole.
  InsTrack run(double progress_base, double progress_share);

 private:
  // The nominal state at every IMU sample is kept for the smoother, and at
  // every update epoch the prior and posterior covariance, the transition
  // from the previous epoch and the error correction applied.
  struct Epoch {
    std::size_t index;                    // IMU sample
    InsErrorMatrix P_prior, P_post, Phi;  // Phi: transition from the previous epoch
    InsErrorVector correction;            // error correction applied at this epoch
    bool reset = false;                   // the filter was reset here: smoothing does not cross it
  };

  void initialise();
  InsErrorMatrix initial_covariance() const;
  void predict(std::size_t i);  // mechanisation from sample i - 1 to i, covariance propagation
  void update(std::size_t i);   // the updates of the epoch ending at sample i
  void update_at_rest();
  void update_moving(std::size_t i, const Eigen::Vector3d& w_now);
  // How an update is gated: NHC by the health monitor's NIS gate; ZUPT and
  // ZARU watched (their NIS feeds the monitor) but never rejected, since the
  // standstill they assert holds whatever the IMU says and the screened IMU
  // cannot make them outliers; the wheel speed by its own gate (slip is not
  // divergence).
  enum class Gating { nis, watched, own };
  void apply(const InsMeasurement& m, Gating gating);
  bool check_health(std::size_t i);  // true when the filter was reset
  void reset_state(std::size_t i);
  void smooth();
  InsErrorVector error_scale() const;
  std::vector<InsErrorVector> smoothed_epoch_errors() const;

  const InsPassInputs& in_;
  const InsSlipOptions& o_;
  const bool aiding_;
  const InsErrorProcess process_;
  const ZeroVelocityUpdate zupt_;
  const ZeroAngularRateUpdate zaru_;
  const NonHolonomicUpdate nhc_;
  const WheelSpeedUpdate wheel_speed_;

  InsState s_;
  Eigen::MatrixXd P_;
  FilterHealthMonitor health_;
  InsTrack track_;
  std::vector<InsState> states_;
  std::vector<Epoch> epochs_;
  InsErrorMatrix Phi_acc_ = InsErrorMatrix::Identity();
  InsErrorVector c_epoch_ = InsErrorVector::Zero();
  double last_update_ = 0;
  std::size_t last_update_index_ = 0;
  Eigen::Vector3d w_sum_ = Eigen::Vector3d::Zero();  // raw rates since the last update (ZARU uses their mean)
  int w_count_ = 0;
};

}  // namespace roverlab::estimation
