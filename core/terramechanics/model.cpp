#include "core/terramechanics/model.h"

#include <cmath>

#include "core/common/error.h"
#include "core/terramechanics/model_impl.h"
#include "core/terramechanics/rft.h"

namespace roverlab::terramechanics {

Traction evaluate(const Soil& soil, const Wheel& wheel, double load, double slip, const ModelOptions& options) {
  Traction t;
  if (!std::isfinite(load) || load <= 0.0 || !std::isfinite(slip) || slip < -1.0 || slip > 1.0 ||
      !(wheel.radius > 0.0) || !(wheel.width > 0.0)) {
    t.status = TractionStatus::invalid_input;
    return t;
  }
  if (options.kind == ModelKind::rft) return evaluate_rft(soil, wheel, load, slip, 0.0, options);
  const auto p = detail::make_params<double>(soil, options.extensions);
  const auto s = detail::solve_any_slip(p, wheel, options, slip, load);
  t.status = s.status;
  if (s.status != TractionStatus::ok) return t;
  t.entry_angle = s.theta0;
  t.max_stress_angle = options.kind != ModelKind::bekker ? s.theta_m : 0.0;
  t.drawbar_pull = s.drawbar;
  t.resistive_torque = s.torque;
  t.sinkage = s.sinkage;
  t.motion_resistance = s.resistance;
  return t;
}

SlipState slip_state(double v, double omega, double radius) {
  const double rw = radius * omega;
  SlipState st;
  if (omega == 0.0 && v == 0.0) return {0.0, 1.0, 7};        // stationary
  if (omega == 0.0) return {-1.0, v > 0.0 ? 1.0 : -1.0, 5};  // locked wheel
  const double dir = omega > 0.0 ? 1.0 : -1.0;
  if (v == 0.0) return {1.0, dir, 6};  // spinning in place
  const bool same_sign = (v > 0.0) == (omega > 0.0);
  if (std::abs(rw) >= std::abs(v)) {
    if (same_sign) return {1.0 - v / rw, dir, 1};  // Eq. 2.8
    return {1.0, dir, 2};
  }
  if (same_sign) return {rw / v - 1.0, dir, 3};  // Eq. 2.9
  return {1.0, dir, 4};
}

const char* to_string(TractionStatus status) {
  switch (status) {
    case TractionStatus::ok:
      return "ok";
    case TractionStatus::unsupported_load:
      return "load not supported with entry angle < 90 deg";
    case TractionStatus::invalid_input:
      return "invalid input";
  }
  return "?";
}

ModelKind parse_model_kind(const std::string& text) {
  if (text == "bekker") return ModelKind::bekker;
  if (text == "wong" || text == "wong-reece") return ModelKind::wong_reece;
  if (text == "ishigami") return ModelKind::ishigami;
  if (text == "rft") return ModelKind::rft;
  throw DataError("unknown model '" + text + "' (bekker, wong, ishigami, rft)");
}

const char* to_string(SlipDefinition d) { return d == SlipDefinition::travel ? "travel" : "longitudinal"; }

SlipDefinition parse_slip_definition(const std::string& text) {
  if (text == "longitudinal") return SlipDefinition::longitudinal;
  if (text == "travel") return SlipDefinition::travel;
  throw DataError("unknown slip definition '" + text + "' (longitudinal, travel)");
}

Integration parse_integration(const std::string& text) {
  if (text == "simpson") return Integration::simpson;
  if (text == "riemann") return Integration::riemann;
  throw DataError("unknown integration '" + text + "' (simpson, riemann)");
}

}  // namespace roverlab::terramechanics
