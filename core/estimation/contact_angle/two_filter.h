#pragma once
// A two-filter fixed-interval smoother over the contact-angle filter of seed
// 000 (issue 15; not in the seed): the filter runs forward over the log and
// again over the log reversed in time, and the two estimates of each state at
// each sample are fused by their variances (Fraser and Potter's smoother,
// with the diagonal of each filter's P). It works over any of the filters
// (fast or generic EKF, UKF), with or without the cross-covariance reset.

#include "core/estimation/contact_angle/contact_angle.h"
#include "core/kinematics/rover_model.h"
#include "core/log/log.h"

namespace roverlab::estimation {

// The log as the rover would have logged it driving its path backwards: the
// imu, joints and wheels streams with t' = t_first + t_last - t (t of the imu
// stream), their samples in reverse order, angular rates, joint rates and
// wheel rates negated; specific force and joint angles unchanged. Other
// streams (truth) are left out.
log::Log reversed_in_time(const log::Log& log);

// The backward run's prior, at least: nearly uninformed at the log's end
// (contact and side-slip angles 0.3 rad = 17 deg, slips 0.1).
constexpr double backward_initial_angle_sigma = 0.3;  // rad
constexpr double backward_initial_slip_sigma = 0.1;

// The forward filter's run with the smoothed states in `estimates` and the
// forward filter's in `filter_estimates`, not yet scored against truth
// (run_contact_angle does that for every method). Yaw is the forward
// filter's (the backward run starts from its own heading).
ContactAngleResult run_contact_angle_two_filter(const log::Log& log, const kinematics::RoverModel& rover,
                                                const ContactAngleOptions& options);

// The same over a forward run already made with `options` and
// record_variance (the model selection's candidate): only the backward run
// and the fusion are done; progress goes from 0.5 to 1.
ContactAngleResult run_contact_angle_two_filter(const log::Log& log, const kinematics::RoverModel& rover,
                                                const ContactAngleOptions& options, ContactAngleResult forward);

}  // namespace roverlab::estimation
