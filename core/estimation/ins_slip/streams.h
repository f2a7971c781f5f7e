#pragma once
// The streams the INS slip detector writes (DESIGN.md: estimator output
// under estimate/<estimator>/); readers name them through these.

#include <vector>

#include "core/log/run_overview.h"

namespace roverlab::estimation::ins_streams {

inline constexpr char kPrefix[] = "estimate/ins/";               // the INS streams
inline constexpr char kOdometryPrefix[] = "estimate/odometry/";  // the odometry written beside them
inline constexpr char kPose[] = "estimate/ins/pose";
inline constexpr char kVelocity[] = "estimate/ins/velocity";
inline constexpr char kBias[] = "estimate/ins/bias";
inline constexpr char kStandstill[] = "estimate/ins/standstill";
inline constexpr char kSlip[] = "estimate/ins/slip";
// Plain wheel odometry from the INS's initial pose, written beside it.
inline constexpr char kOdometryPose[] = "estimate/odometry/pose";

// The pose sources a log may carry, best first: simulated truth (truth/motion
// east/north, the planar truth/pose x/z, or truth/body velocities
// integrated), GPS (east/north), the INS estimate, wheel odometry (this
// estimator's, else the logged odometry x/y).
inline const std::vector<analysis::PoseSource> kPoseSources = {
    {"truth/motion", "east", "north", "simulated truth"},
    {"truth/pose", "x", "z", "simulated planar truth"},
    {"truth/body", "velocity_x", nullptr, "simulated truth's integrated velocity"},
    {"gps", "east", "north", "GPS track"},
    {kPose, "east", "north", "INS estimate"},
    {kOdometryPose, "east", "north", "wheel odometry"},
    {"odometry", "x", "y", "logged wheel odometry"}};

}  // namespace roverlab::estimation::ins_streams
