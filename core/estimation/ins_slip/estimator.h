#pragma once
// The INS slip estimator of seed 002 as named steps: set-up (samples,
// standstill detection, levelling and initial heading), the localisation
// pass (with wheel-speed aiding if asked), the slip detector's pass without
// it, and the output streams. It produces streams only; scoring against a
// reference is core/estimation/ins_slip/metrics.h.

#include <vector>

#include "core/estimation/ins_slip/filter.h"
#include "core/estimation/ins_slip/ins_slip.h"
#include "core/models/reference_track.h"

namespace roverlab::estimation {

class InsSlipEstimator {
 public:
  // Reads and checks the streams, finds the standstill samples and levels.
  // Throws DataError as run_ins_slip does.
  InsSlipEstimator(const log::Log& log, const InsSlipOptions& options, const InsSlipChannels& channels = {});

  // Streams estimate/ins/{pose,velocity,bias,standstill,slip} and
  // estimate/odometry/pose, with the input's metadata.
  log::Log run();
  // What the IMU screening and both filter passes rejected, bridged and reset (after run).
  const HealthReport& health() const { return health_; }
  // How the initial heading was obtained (after run).
  const InitialHeading& initial_heading() const { return heading_; }
  const ReferenceTrack& reference() const { return reference_; }
  // The |s| band of the "none" class (InsSlipOptions::no_slip).
  double no_slip() const;
  // The IMU's vibration and what it leaves the detector (ImuVibration).
  ImuVibration vibration() const;

 private:
  // Slip at the wheel samples within the IMU span, with its reference.
  struct SlipColumns {
    std::vector<double> time, slip, slip_class, wheel_speed, forward_speed, at_rest;
    std::vector<double> reference_speed, reference_slip, reference_class;
  };

  void read_samples();
  void detect_standstill();
  void level();
  void align_initial_pose();
  double pass_share() const;  // each filter pass's share of the progress
  void add_navigation_streams(log::Log& out, const InsTrack& track) const;
  SlipColumns slip_columns(const InsTrack& detector) const;
  void add_reference_slip(SlipColumns& c, double t, double wheel_speed, bool at_rest, bool turning) const;
  void add_slip_stream(log::Log& out, const InsTrack& detector) const;
  void add_odometry_stream(log::Log& out) const;

  const log::Log& log_;
  const InsSlipOptions o_;
  const InsSlipChannels channels_;
  const log::Stream* imu_ = nullptr;
  const log::Stream* truth_slip_ = nullptr;  // slip reference when present, else GPS
  ReferenceTrack reference_;
  InsPassInputs in_;
  ScreenedImu imu_screened_;  // the IMU channels the passes read
  HealthReport health_;
  InitialHeading heading_;
};

}  // namespace roverlab::estimation
