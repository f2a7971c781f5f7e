#pragma once
// DESIGN.md's log conventions as names: estimator output under
// estimate/<estimator>/ (each estimator names its own streams in
// core/estimation/<family>/streams.h), simulated ground truth under truth/.

namespace roverlab::log {

inline constexpr char kEstimatePrefix[] = "estimate/";
inline constexpr char kTruthPrefix[] = "truth/";

}  // namespace roverlab::log
