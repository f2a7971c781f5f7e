#pragma once
// The streams the contact-angle estimator writes (DESIGN.md: estimator
// output under estimate/<estimator>/); readers name them through these.

namespace roverlab::estimation::contact_streams {

inline constexpr char kPrefix[] = "estimate/contact/";        // every stream it writes
inline constexpr char kBody[] = "estimate/contact/body";      // attitude and body velocity
inline constexpr char kWheels[] = "estimate/contact/wheels";  // per-wheel slip, contact and side-slip angles

}  // namespace roverlab::estimation::contact_streams
