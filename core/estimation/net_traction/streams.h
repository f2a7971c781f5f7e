#pragma once
// The streams the net-traction estimators write (DESIGN.md: estimator
// output under estimate/<estimator>/); readers name them through these.

namespace roverlab::estimation::net_traction_streams {

inline constexpr char kPrefix[] = "estimate/net_traction/";  // every stream it writes
inline constexpr char kWheels[] = "estimate/net_traction/wheels";
inline constexpr char kBody[] = "estimate/net_traction/body";

}  // namespace roverlab::estimation::net_traction_streams
