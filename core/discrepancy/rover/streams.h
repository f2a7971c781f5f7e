#pragma once
// The streams the rover discrepancy study writes (DESIGN.md: estimator
// output under estimate/<estimator>/); readers name them through these.

namespace roverlab::analysis::rover_streams {

inline constexpr char kPrefix[] = "estimate/rover_discrepancy/";  // every stream it writes
// Prefixes: one stream per measured stream, the measured stream's name appended.
inline constexpr char kResidualNominal[] = "estimate/rover_discrepancy/residual_nominal/";
inline constexpr char kResidualWithCauses[] = "estimate/rover_discrepancy/residual_with_causes/";
// The RMS over channels of the residual in noise sigmas, before and after.
inline constexpr char kResiduals[] = "estimate/rover_discrepancy/residuals";

}  // namespace roverlab::analysis::rover_streams
