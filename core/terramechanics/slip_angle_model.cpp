#include "core/terramechanics/slip_angle_model.h"

#include <cmath>
#include <utility>
#include <vector>

#include "core/terramechanics/model_impl.h"
#include "core/terramechanics/rft.h"

namespace roverlab::terramechanics {

namespace {

using detail::kGravity;
using detail::kPi;

struct Node {
  double theta, weight;
};

// The quadrature of the Wong-Reece model (model_impl.h): Simpson on the two
// zones (Eq. 2.25, seed 003) or the midpoint Riemann sum.
// The contact runs from the rear angle theta_r <= 0 to theta0.
// Written into `out` (cleared; its capacity kept across a solve's calls).
void nodes(const ModelOptions& o, double theta0, double theta_m, double theta_r, std::vector<Node>& out) {
  out.clear();
  if (o.integration == Integration::simpson) {
    const double front = (theta0 - theta_m) / 6.0, rear = (theta_m - theta_r) / 6.0;
    out.push_back({theta0, front});
    out.push_back({0.5 * (theta0 + theta_m), 4.0 * front});
    out.push_back({theta_m, front + rear});
    out.push_back({0.5 * (theta_m + theta_r), 4.0 * rear});
    out.push_back({theta_r, rear});
    return;
  }
  out.reserve(static_cast<std::size_t>(o.riemann_points));
  const double h = (theta0 - theta_r) / o.riemann_points;
  for (int k = 0; k < o.riemann_points; ++k) out.push_back({theta_r + h * (k + 0.5), h});
}

// The soil's values after the soil-strength factor, and the wheel's shear radius.
struct Setup {
  double r, b, rs, n, c, tan_phi, modulus, k_x, k_y, gamma, rear_angle_ratio, sidewall_scale;
  bool peak;                    // the peaked shear curve (model.h): k_x is then K_w (1 + k_s s)
  double shear_residual_ratio;  // its K_r
};

Setup setup(const Soil& soil, const Wheel& w, const Extensions& e, double s) {
  Setup u{};
  const double f = e.soil_strength;
  u.r = w.radius;
  u.b = w.width;
  const bool grousers = e.grousers && w.grouser_count > 0 && w.grouser_height > 0.0;
  u.rs = grousers ? w.radius + e.grouser_effectiveness * w.grouser_height : w.radius;
  u.n = soil.n + e.slip_sinkage_n1 * s;  // slip-sinkage, Ding et al. 2011
  u.c = f * soil.cohesion;
  u.tan_phi = f * std::tan(soil.friction_angle);
  u.modulus = (f * soil.kc + f * soil.kphi * u.b) * std::pow(u.b, u.n - 1.0);  // Eq. 2.12-2.13, seed 003
  u.peak = e.shear_peak;
  u.shear_residual_ratio = e.shear_residual_ratio;
  const double k0 = u.peak ? e.shear_peak_displacement : soil.shear_modulus;
  u.k_x = k0 * (1.0 + e.shear_modulus_slip * s);  // K(s), Ding et al. 2015 (model.h)
  u.k_y = soil.lateral_shear_modulus > 0.0 ? soil.lateral_shear_modulus : u.k_x;
  u.rear_angle_ratio = e.rear_angle_ratio;
  u.sidewall_scale = e.sidewall_scale;
  u.gamma = soil.density * kGravity;
  return u;
}

// The shear stress's share of the strength at x = j / k (model_impl.h).
double shear_fraction(const Setup& u, double x) { return detail::shear_fraction(u.peak, x, u.shear_residual_ratio); }

struct Integrals {
  double normal = 0.0, drawbar = 0.0, torque = 0.0, lateral_shear = 0.0, sidewall = 0.0;
};

// Hegedus's bulldozing coefficients of a soil: they depend on phi only, so
// the stress integral computes them once, not at every node.
struct SidewallCoefficients {
  double d1 = 0.0, d2 = 0.0;
};

SidewallCoefficients sidewall_coefficients(double tan_phi) {
  const double phi = std::atan(tan_phi);
  const double xc = kPi / 4.0 - phi / 2.0;  // destructive angle X_c = 45 deg - phi / 2 (Hegedus)
  const double cot_xc = 1.0 / std::tan(xc);
  return {cot_xc + std::tan(xc + phi),          // D_1(X_c), Ishigami 2007 Eq. 10
          cot_xc + cot_xc * cot_xc * tan_phi};  // D_2(X_c) = cot X_c + cot^2 X_c / cot phi
}

double sidewall_per_length(const SidewallCoefficients& k, double c, double gamma, double h) {
  if (!(h > 0.0)) return 0.0;
  return k.d1 * (c * h + k.d2 * gamma * h * h / 2.0);  // R_b, Eq. 10 (gamma: weight density, see docs)
}

// Stress integrals at entry angle theta0, longitudinal slip s in [0, 1] and
// lateral velocity ratio lateral = v_y / (r w) (Ishigami: (1 - s) tan beta).
// With normal_only, only the normal force (what the sinkage solve needs),
// computed by the same operations as in the full integral.
Integrals integrate(const Setup& u, const ModelOptions& o, const LateralOptions& lat, double s, double lateral,
                    double theta0, double c1, double c2, std::vector<Node>& buffer, bool normal_only = false) {
  const double theta_m = theta0 * (c1 + c2 * s);  // Eq. 2.10, seed 003; Eq. 4, Ishigami 2007
  const double cos0 = std::cos(theta0), sin0 = std::sin(theta0);
  Integrals in;
  double i_sigma_cos = 0, i_sigma_sin = 0, i_tau_cos = 0, i_tau_sin = 0, i_tau = 0, i_tau_y = 0, i_side = 0;
  const double theta_r = -u.rear_angle_ratio * theta0;  // rear angle (model.h)
  const SidewallCoefficients side = normal_only ? SidewallCoefficients{} : sidewall_coefficients(u.tan_phi);
  nodes(o, theta0, theta_m, theta_r, buffer);
  for (const Node& node : buffer) {
    const double th = node.theta;
    // At the entry angle sigma and both shear displacements are exactly 0, so
    // is every term below: the node is skipped (the same sums, bit for bit).
    if (th == theta0) continue;
    // Eq. 2.11 and 2.14, seed 003 (Eq. 3 of Ishigami 2007 with Wong's moduli).
    // In the front zone th_eq is th, whose cosine is ct; at theta_r it is theta0.
    const double ct = std::cos(th), st = std::sin(th);
    const bool front_zone = th >= theta_m;
    const double th_eq = front_zone ? th : theta0 - (th - theta_r) / (theta_m - theta_r) * (theta0 - theta_m);
    const double c_eq = front_zone ? ct : th == theta_r ? cos0 : std::cos(th_eq);
    const double sigma = u.modulus * detail::power(u.r / u.b * (c_eq - cos0), u.n);
    const double strength = u.c + sigma * u.tan_phi;
    const double j_x = u.rs * ((theta0 - th) - (1.0 - s) * (sin0 - st));  // Eq. 6
    const double j_y = u.rs * lateral * (theta0 - th);                    // Eq. 8: r (1 - s)(theta0 - theta) tan(beta)
    double tau_x = 0.0, tau_y = 0.0;
    if (lat.shear == LateralShear::independent) {
      tau_x = strength * shear_fraction(u, j_x / u.k_x);  // Eq. 5
      if (!normal_only) {
        tau_y = std::copysign(strength * shear_fraction(u, std::abs(j_y) / u.k_y), j_y);  // Eq. 7
      }
    } else {
      const double ux = j_x / u.k_x, uy = j_y / u.k_y;
      const double big_j = std::hypot(ux, uy);
      if (big_j > 0.0) {
        const double tau = strength * shear_fraction(u, big_j);
        tau_x = tau * ux / big_j;
        tau_y = tau * uy / big_j;
      }
    }
    i_sigma_cos += node.weight * sigma * ct;
    i_tau_sin += node.weight * tau_x * st;
    if (normal_only) continue;
    i_sigma_sin += node.weight * sigma * st;
    i_tau_cos += node.weight * tau_x * ct;
    i_tau += node.weight * tau_x;
    i_tau_y += node.weight * tau_y;
    const double h = u.r * (ct - cos0);  // depth of the sidewall point, Eq. 10
    i_side += node.weight * sidewall_per_length(side, u.c, u.gamma, h) * (u.r - h * ct);
  }
  in.normal = u.b * (u.r * i_sigma_cos + u.rs * i_tau_sin);      // Eq. 11 (Eq. 2.20, seed 003)
  in.drawbar = u.b * (u.rs * i_tau_cos - u.r * i_sigma_sin);     // Eq. 9 (Eq. 2.21)
  in.torque = u.b * u.rs * u.rs * i_tau;                         // Eq. 12 (Eq. 2.22)
  in.lateral_shear = u.b * u.rs * i_tau_y;                       // Eq. 10, first term
  in.sidewall = lat.sidewall_scale * u.sidewall_scale * i_side;  // Eq. 10, second term (one sidewall)
  return in;
}

struct Solved {
  TractionStatus status = TractionStatus::unsupported_load;
  double theta0 = 0.0;
  Integrals in;
};

// Entry angle from the vertical balance F_z = W (Eq. 11) on (0, pi/2], the
// normal force rising from 0: secant steps on log F_z against log theta0
// (nearly linear, as in the Wong-Reece solver), kept inside the bracket,
// bisection when a step leaves it.
template <class Normal>
bool cold_root(const Normal& normal_at, double n, double load, double& root) {
  double lo = 0.0, hi = kPi / 2.0;
  const double n_hi = normal_at(hi);
  if (!(n_hi >= load)) return false;
  double th = hi * std::pow(load / n_hi, 1.0 / (2.0 * n + 1.0));  // small-angle power law
  double prev_th = hi, prev_n = n_hi;
  root = th;
  for (int it = 0; it < 200 && hi - lo > 1e-15; ++it) {
    if (!(th > lo && th < hi)) th = 0.5 * (lo + hi);
    const double nv = normal_at(th);
    root = th;
    if (std::abs(nv - load) <= 1e-13 * load) break;
    (nv < load ? lo : hi) = th;
    double next = 0.5 * (lo + hi);
    if (nv > 0.0 && prev_n > 0.0 && nv != prev_n && th != prev_th) {
      next = th * std::exp(std::log(load / nv) * std::log(th / prev_th) / std::log(nv / prev_n));
    }
    prev_th = th;
    prev_n = nv;
    th = next;
  }
  return true;  // the last angle evaluated: within the tolerance or the bracket's width
}

Solved solve(const Soil& soil, const Wheel& w, const ModelOptions& o, const LateralOptions& lat, double s,
             double lateral, double load, double* hint) {
  const Setup u = setup(soil, w, o.extensions, s);
  thread_local std::vector<Node> buffer;  // the nodes, without an allocation per solve
  auto normal_at = [&](double th) {
    return integrate(u, o, lat, s, lateral, th, soil.c1, soil.c2, buffer, true).normal;
  };
  Solved out;
  double root = 0.0;
  const bool warm = hint != nullptr && *hint > 0.0 && detail::warm_root(normal_at, u.n, load, *hint, 1e-13, root);
  if (!warm && !cold_root(normal_at, u.n, load, root)) return out;
  if (hint != nullptr) *hint = root;
  out.status = TractionStatus::ok;
  out.theta0 = root;
  out.in = integrate(u, o, lat, s, lateral, root, soil.c1, soil.c2, buffer);
  return out;
}

}  // namespace

double lateral_shear_modulus(const Soil& soil) {
  return soil.lateral_shear_modulus > 0.0 ? soil.lateral_shear_modulus : soil.shear_modulus;
}

double sidewall_resistance(const Soil& soil, double soil_strength, double depth) {
  const double tan_phi = soil_strength * std::tan(soil.friction_angle);
  return sidewall_per_length(sidewall_coefficients(tan_phi), soil_strength * soil.cohesion, soil.density * kGravity,
                             depth);
}

SlipAngleTraction evaluate_slip_angle(const Soil& soil, const Wheel& wheel, double load, double slip, double slip_angle,
                                      const ModelOptions& options, const LateralOptions& lateral,
                                      EntryAngleHint* hint) {
  if (options.kind == ModelKind::rft) return evaluate_rft(soil, wheel, load, slip, slip_angle, options);
  SlipAngleTraction t;
  t.slip_angle = slip_angle;
  if (!std::isfinite(load) || load <= 0.0 || !std::isfinite(slip) || slip < -1.0 || slip > 1.0 ||
      !std::isfinite(slip_angle) || std::abs(slip_angle) > kPi / 2.0 || !(wheel.radius > 0.0) || !(wheel.width > 0.0) ||
      options.kind == ModelKind::bekker || !std::isfinite(lateral.sidewall_scale) || lateral.sidewall_scale < 0.0) {
    t.status = TractionStatus::invalid_input;
    return t;
  }
  // The longitudinal slip and lateral velocity ratio v_y / (r w) of the
  // measured slip (SlipDefinition, model.h).
  const bool travel = options.slip_definition == SlipDefinition::travel;
  const double s_x = travel ? 1.0 - (1.0 - slip) * std::cos(slip_angle) : slip;
  const double v_y = travel ? (1.0 - slip) * std::sin(slip_angle) : 0.0;
  // Driving, (1 - s_x) tan(beta) = v_y / (r w) exactly; v_y stays finite at
  // 90 deg. Skidding (s_x < 0, only below 60 deg) mirrors the slip as the
  // longitudinal reading does, so a travel slip is its velocity's
  // longitudinal slip there too.
  const bool lateral_of_travel = travel && s_x >= 0.0;
  auto lateral_ratio = [&](double s_used) { return lateral_of_travel ? v_y : (1.0 - s_used) * std::tan(slip_angle); };
  const double s = std::abs(s_x);
  const Solved main = solve(soil, wheel, options, lateral, s, lateral_ratio(s), load, hint ? &hint->entry : nullptr);
  t.status = main.status;
  if (main.status != TractionStatus::ok) return t;
  const auto p = detail::make_params<double>(soil, options.extensions);
  // Bulldozing ahead of the wheel (model.h), at the sinkage of entry angle th.
  auto bulldozed = [&](double drawbar, double th) {
    if (!options.extensions.bulldozing) return drawbar;
    return drawbar -
           p.bulldozing_scale * detail::bulldozing_resistance(p, wheel.width, wheel.radius * (1.0 - std::cos(th)));
  };
  double drawbar = bulldozed(main.in.drawbar, main.theta0), torque = main.in.torque;
  if (s_x < 0.0) {
    // Skid by anti-symmetry about the s = 0 values (Eq. 2.26-2.27, seed 003),
    // at the same slip angle; entry angle and lateral force of the mirrored slip.
    const Solved zero =
        solve(soil, wheel, options, lateral, 0.0, lateral_ratio(0.0), load, hint ? &hint->zero_slip_entry : nullptr);
    t.status = zero.status;
    if (zero.status != TractionStatus::ok) return t;
    drawbar = -drawbar + 2.0 * bulldozed(zero.in.drawbar, zero.theta0);
    torque = -torque + 2.0 * zero.in.torque;
  }
  t.entry_angle = main.theta0;
  t.max_stress_angle = main.theta0 * (soil.c1 + soil.c2 * s);
  t.sinkage = wheel.radius * (1.0 - std::cos(main.theta0));
  t.drawbar_pull = drawbar;
  t.resistive_torque = torque;
  // The soil resists the lateral motion: F_y opposes beta (sign convention above).
  const double side = slip_angle > 0.0 ? 1.0 : slip_angle < 0.0 ? -1.0 : 0.0;
  t.lateral_shear = main.in.lateral_shear == 0.0 ? 0.0 : -main.in.lateral_shear;
  t.sidewall = side == 0.0 ? 0.0 : -side * main.in.sidewall;
  t.lateral_force = t.lateral_shear + t.sidewall;
  return t;
}

}  // namespace roverlab::terramechanics
