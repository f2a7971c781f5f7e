#pragma once
// The wheel-soil model as templates over the scalar type, so that the same
// code gives values (double) and derivatives (ceres::Jet) for soil
// identification. Internal to core/terramechanics.

#include <cmath>
#include <type_traits>

#include "core/terramechanics/model.h"

namespace roverlab::terramechanics::detail {

using std::atan;
using std::cos;
using std::exp;
using std::log;
using std::pow;
using std::sin;
using std::sqrt;
using std::tan;

constexpr double kPi = 3.14159265358979323846;
constexpr double kGravity = 9.80665;

// Parameters a fit may vary, as scalars of type T.
template <typename T>
struct Params {
  T n, cohesion, tan_phi, shear_modulus, kc, kphi, c1, c2, density;
  T slip_sinkage_n1, grouser_effectiveness, bulldozing_scale, soil_strength;
  T shear_modulus_slip, rear_angle_ratio, shear_residual_ratio, shear_peak_displacement;
};

template <typename T>
Params<T> make_params(const Soil& s, const Extensions& e) {
  return Params<T>{T(s.n),
                   T(s.cohesion),
                   T(std::tan(s.friction_angle)),
                   T(s.shear_modulus),
                   T(s.kc),
                   T(s.kphi),
                   T(s.c1),
                   T(s.c2),
                   T(s.density),
                   T(e.slip_sinkage_n1),
                   T(e.grouser_effectiveness),
                   T(e.bulldozing_scale),
                   T(e.soil_strength),
                   T(e.shear_modulus_slip),
                   T(e.rear_angle_ratio),
                   T(e.shear_residual_ratio),
                   T(e.shear_peak_displacement)};
}

template <typename T>
struct Integrals {
  T normal;   // vertical reaction, Eq. 2.20 (2.5 for Bekker)
  T drawbar;  // Eq. 2.21 (2.6)
  T torque;   // Eq. 2.22 (2.7)
  // The normal stresses' share of -drawbar (the b r sigma sin(theta) term of
  // Eq. 2.21 / 2.6): the compaction resistance, which opposes the centre's
  // motion whichever way the wheel turns.
  T resistance;
};

// x^n for x >= 0, with x = 0 giving exactly 0 (and a zero derivative).
template <typename T>
T power(const T& x, const T& n) {
  if (!(x > 0.0)) return T(0.0);
  return exp(n * log(x));
}

// The peaked ("hump") shear curve tau / tau_max at x = j / K_w (Wong, Theory
// of Ground Vehicles, ch. 2): K_r [1 + (1 / (K_r (1 - 1/e)) - 1) e^(1 - x)]
// (1 - e^-x), written K_r + (e / (e - 1) - K_r) e^(1 - x) in the bracket.
template <typename T>
T peaked_shear(const T& x, const T& residual_ratio) {
  constexpr double kE = 2.71828182845904523536;
  return (residual_ratio + (kE / (kE - 1.0) - residual_ratio) * exp(1.0 - x)) * (1.0 - exp(-x));
}

// The shear stress's share of the strength c + sigma tan phi at x = j / K:
// 1 - exp(-x) (Eq. 2.19; Ishigami 2007 Eq. 5 and 7), or the peaked curve
// with residual ratio K_r when the extension is on (K is then K_w).
template <typename T>
T shear_fraction(bool peak, const T& x, const T& residual_ratio) {
  return peak ? peaked_shear(x, residual_ratio) : 1.0 - exp(-x);
}

// Bekker's stress integrals (Eq. 2.1-2.7, seed 003) for entry angle theta0.
template <typename T>
Integrals<T> bekker_integrals(const Wheel& w, const ModelOptions& o, const T& c, const T& tan_phi, const T& kc,
                              const T& kphi, const T& n, const T& theta0) {
  const double r = w.radius, b = w.width;
  const T cos0 = cos(theta0);
  Integrals<T> out{T(0.0), T(0.0), T(0.0), T(0.0)};
  const T modulus = kc / b + kphi;
  auto sample = [&](const T& th, T& sigma, T& tau) {
    sigma = modulus * power(T(r) * (cos(th) - cos0), n);  // Eq. 2.1, seed 003
    tau = c + sigma * tan_phi;                            // Eq. 2.4
  };
  auto add = [&](const T& th, const T& weight) {
    T sigma, tau;
    sample(th, sigma, tau);
    out.normal += weight * sigma * cos(th);                     // Eq. 2.5
    out.drawbar += weight * (tau * cos(th) - sigma * sin(th));  // Eq. 2.6
    out.torque += weight * tau;                                 // Eq. 2.7
    out.resistance += weight * sigma * sin(th);
  };
  if (o.integration == Integration::simpson) {
    const T h = theta0 / 4.0;  // composite Simpson, two panels (five points)
    const double wts[5] = {1, 4, 2, 4, 1};
    for (int k = 0; k < 5; ++k) add(h * double(k), h / 3.0 * wts[k]);
  } else {
    const T h = theta0 / double(o.riemann_points);
    for (int k = 0; k < o.riemann_points; ++k) add(h * (k + 0.5), h);
  }
  out.normal *= b * r;
  out.drawbar *= b * r;
  out.torque *= b * r * r;
  out.resistance *= b * r;
  return out;
}

// The soil's and wheel's values at slip s that do not depend on the entry
// angle: computed once per solve, not at every integral of its root search.
template <typename T>
struct SlipTerms {
  T c, tan_phi, kc, kphi, n, rs, modulus, shear_modulus;
};

template <typename T>
SlipTerms<T> slip_terms(const Params<T>& p, const Wheel& w, const ModelOptions& o, double s) {
  const double b = w.width;
  const T f = p.soil_strength;
  SlipTerms<T> k;
  k.c = f * p.cohesion;
  k.tan_phi = f * p.tan_phi;
  k.kc = f * p.kc;
  k.kphi = f * p.kphi;
  k.n = p.n + p.slip_sinkage_n1 * s;  // slip-sinkage, Ding et al. 2011
  const bool grousers = o.extensions.grousers && w.grouser_count > 0 && w.grouser_height > 0.0;
  k.rs = grousers ? w.radius + p.grouser_effectiveness * w.grouser_height : T(w.radius);
  k.modulus = o.kind == ModelKind::bekker ? T(0.0) : (k.kc + k.kphi * b) * pow(T(b), k.n - 1.0);  // Eq. 2.12-2.13
  // Slip-dependent shear deformation modulus K = K_0 (1 + k_s s) (Ding et al. 2015, doi:10.1002/rob.21533).
  // The hump curve's K_w takes K_0's place.
  k.shear_modulus =
      (o.extensions.shear_peak ? p.shear_peak_displacement : p.shear_modulus) * (1.0 + p.shear_modulus_slip * s);
  return k;
}

// Stress integrals for entry angle theta0 and slip s >= 0, with s's terms k.
template <typename T>
Integrals<T> integrals(const Params<T>& p, const SlipTerms<T>& k, const Wheel& w, const ModelOptions& o, double s,
                       const T& theta0) {
  const double r = w.radius, b = w.width;
  const T &c = k.c, &tan_phi = k.tan_phi, &n = k.n, &rs = k.rs;
  const T cos0 = cos(theta0), sin0 = sin(theta0);
  Integrals<T> out{T(0.0), T(0.0), T(0.0), T(0.0)};

  if (o.kind == ModelKind::bekker) return bekker_integrals(w, o, c, tan_phi, k.kc, k.kphi, n, theta0);

  // Wong-Reece.
  const T& modulus = k.modulus;
  const T theta_m = theta0 * (p.c1 + p.c2 * s);  // Eq. 2.10
  // Rear angle (rebound): contact down to theta_r = -kappa theta_0 behind
  // the bottom dead centre (Wong & Reece 1967; Ishigami et al. 2007 Eq. 6).
  const T theta_r = -p.rear_angle_ratio * theta0;
  const bool peak = o.extensions.shear_peak;
  const T& shear_modulus = k.shear_modulus;
  // sigma and tau at angle th, whose cosine and sine are ct and st.
  auto sample = [&](const T& th, const T& ct, const T& st, T& sigma, T& tau) {
    // Eq. 2.11 (front zone) and 2.14 (rear zone, mirrored onto the front);
    // in the front zone th_eq is th, whose cosine is known.
    const bool front_zone = th >= theta_m;
    const T th_eq = front_zone ? th : theta0 - (th - theta_r) / (theta_m - theta_r) * (theta0 - theta_m);
    // At theta_r, th_eq is theta0 exactly (its cosine is cos0).
    const T c_eq = front_zone ? ct : th == theta_r ? cos0 : T(cos(th_eq));
    sigma = modulus * power(T(r / b) * (c_eq - cos0), n);
    const T j = rs * ((theta0 - th) - (1.0 - s) * (sin0 - st));                                     // Eq. 2.18
    tau = (c + sigma * tan_phi) * shear_fraction(peak, j / shear_modulus, p.shear_residual_ratio);  // Eq. 2.19
  };
  T i_sigma_cos(0.0), i_sigma_sin(0.0), i_tau_cos(0.0), i_tau_sin(0.0), i_tau(0.0);
  auto add = [&](const T& th, const T& weight) {
    const T ct = cos(th), st = sin(th);
    T sigma, tau;
    sample(th, ct, st, sigma, tau);
    i_sigma_cos += weight * sigma * ct;
    i_sigma_sin += weight * sigma * st;
    i_tau_cos += weight * tau * ct;
    i_tau_sin += weight * tau * st;
    i_tau += weight * tau;
  };
  if (o.integration == Integration::simpson) {
    // Eq. 2.25: Simpson on [theta_m, theta_0] and on [theta_r, theta_m].
    const T front = (theta0 - theta_m) / 6.0, rear = (theta_m - theta_r) / 6.0;
    // The node at theta0 adds exactly 0 (sigma and j are 0 there, their
    // derivatives too): skipped.
    add((theta0 + theta_m) * 0.5, 4.0 * front);
    add(theta_m, front + rear);
    add((theta_m + theta_r) * 0.5, 4.0 * rear);
    add(theta_r, rear);
  } else {
    const T h = (theta0 - theta_r) / double(o.riemann_points);
    for (int k = 0; k < o.riemann_points; ++k) add(theta_r + h * (k + 0.5), h);
  }
  out.normal = b * (r * i_sigma_cos + rs * i_tau_sin);   // Eq. 2.20
  out.drawbar = b * (rs * i_tau_cos - r * i_sigma_sin);  // Eq. 2.21
  out.torque = b * rs * rs * i_tau;                      // Eq. 2.22
  out.resistance = b * r * i_sigma_sin;
  return out;
}

template <typename T>
Integrals<T> integrals(const Params<T>& p, const Wheel& w, const ModelOptions& o, double s, const T& theta0) {
  return integrals(p, slip_terms(p, w, o, s), w, o, s, theta0);
}

// Bulldozing resistance for sinkage z (Bekker; Wong, Theory of Ground
// Vehicles, Eq. 2.79) with Terzaghi/Vesic bearing-capacity factors.
template <typename T>
T bulldozing_resistance(const Params<T>& p, double width, const T& z) {
  const T tan_phi = p.soil_strength * p.tan_phi;
  const T c = p.soil_strength * p.cohesion;
  const T phi = atan(tan_phi);
  const T nq = exp(kPi * tan_phi) * pow(tan(kPi / 4.0 + phi / 2.0), 2.0);
  const T nc = (nq - 1.0) / tan_phi;
  const T ngamma = 2.0 * (nq + 1.0) * tan_phi;
  const T cos2 = cos(phi) * cos(phi);
  const T kc = (nc - tan_phi) * cos2;
  const T kgamma = (2.0 * ngamma / tan_phi + 1.0) * cos2;
  const T gamma = p.density * kGravity;
  return width * (0.67 * c * z * kc + 0.5 * z * z * gamma * kgamma);
}

template <typename T>
struct Solution {
  TractionStatus status = TractionStatus::invalid_input;
  T theta0, theta_m, drawbar, torque, sinkage, resistance;
};

inline double value_of(double x) { return x; }
template <typename J>
double value_of(const J& x) {
  return x.a;
}

// The parameters' values (a Jet's real parts).
template <typename T>
Params<double> value_params(const Params<T>& p) {
  if constexpr (std::is_same_v<T, double>) {
    return p;
  } else {
    return Params<double>{value_of(p.n),
                          value_of(p.cohesion),
                          value_of(p.tan_phi),
                          value_of(p.shear_modulus),
                          value_of(p.kc),
                          value_of(p.kphi),
                          value_of(p.c1),
                          value_of(p.c2),
                          value_of(p.density),
                          value_of(p.slip_sinkage_n1),
                          value_of(p.grouser_effectiveness),
                          value_of(p.bulldozing_scale),
                          value_of(p.soil_strength),
                          value_of(p.shear_modulus_slip),
                          value_of(p.rear_angle_ratio),
                          value_of(p.shear_residual_ratio),
                          value_of(p.shear_peak_displacement)};
  }
}

// The entry angle whose normal force is `load` (Eq. 2.24), bracketed in
// (0, pi/2] and found by secant steps on log(normal force) against
// log(theta0), which is nearly linear, safeguarded by bisection; n the
// sinkage exponent. False when even pi/2 does not carry the load.
template <class Normal>
bool entry_angle_root(const Normal& normal, double load, double n, double& root) {
  double hi = kPi / 2.0;
  double n_hi = normal(hi);
  if (!(n_hi >= load)) return false;
  double lo = 0.0;
  // Start from the small-angle power law N ~ theta^(2n+1) through (hi, n_hi).
  const double exponent0 = 2.0 * n + 1.0;
  double th = hi * std::pow(load / n_hi, 1.0 / exponent0);
  double prev_th = hi, prev_n = n_hi;
  root = th;
  for (int it = 0; it < 60; ++it) {
    if (!(th > lo && th < hi)) th = 0.5 * (lo + hi);
    const double nv = normal(th);
    root = th;
    if (std::abs(nv - load) <= 1e-10 * load || hi - lo < 1e-13) break;
    if (nv < load) {
      lo = th;
    } else {
      hi = th;
      n_hi = nv;
    }
    double next;
    if (nv > 0.0 && prev_n > 0.0 && prev_th != th && std::abs(std::log(nv / prev_n)) > 1e-300) {
      const double slope = std::log(nv / prev_n) / std::log(th / prev_th);
      next = th * std::exp(std::log(load / nv) / slope);
    } else {
      next = 0.5 * (lo + hi);
    }
    prev_th = th;
    prev_n = nv;
    th = next;
  }
  return true;
}

// The same root from a previous one (a fit evaluates each point again and
// again at nearby parameters): a step along the power law F_z ~
// theta0^(2n+1), then secant steps on the logs, at most 4 evaluations, each
// inside (0, pi/2). False (start cold) unless one is within tol x load.
template <class Normal>
bool warm_root(const Normal& normal_at, double n, double load, double hint, double tol, double& root) {
  double th = hint, prev_th = 0.0, prev_n = 0.0;
  for (int it = 0; it < 4; ++it) {
    if (!(th > 0.0 && th < kPi / 2.0)) return false;
    const double nv = normal_at(th);
    if (std::abs(nv - load) <= tol * load) {
      root = th;
      return true;
    }
    if (!(nv > 0.0)) return false;
    const double slope =
        it == 0 || nv == prev_n || th == prev_th ? 2.0 * n + 1.0 : std::log(nv / prev_n) / std::log(th / prev_th);
    if (!(slope > 0.0)) return false;
    prev_th = th;
    prev_n = nv;
    th = th * std::exp(std::log(load / nv) / slope);
  }
  return false;
}

// Entry angle theta0 from vertical equilibrium (Eq. 2.24) and the traction
// at slip s >= 0. The root is bracketed in (0, pi/2] and found by secant
// steps on log(normal force) against log(theta0), which is nearly linear,
// safeguarded by bisection. For Jets, one Newton step from the converged
// root carries d theta0 / d parameters (implicit function theorem). With a
// hint (the last entry angle of the same point, 0 if none), the root is
// first sought from there (warm_root) and the hint updated.
template <typename T>
Solution<T> solve(const Params<T>& p, const Wheel& w, const ModelOptions& o, double s, double load,
                  double* hint = nullptr) {
  Solution<T> out;
  const Params<double> pv = value_params(p);
  const SlipTerms<double> kv = slip_terms(pv, w, o, s);
  auto normal = [&](double th) { return integrals<double>(pv, kv, w, o, s, th).normal; };
  double root = 0.0;
  const double n = value_of(pv.n);
  const bool warm = hint != nullptr && *hint > 0.0 && warm_root(normal, n, load, *hint, 1e-10, root);
  if (!warm && !entry_angle_root(normal, load, n, root)) {
    out.status = TractionStatus::unsupported_load;
    return out;
  }
  if (hint != nullptr) *hint = root;
  T theta0 = T(root);
  Integrals<T> in;
  if constexpr (!std::is_same_v<T, double>) {
    // At the root with the parameters' derivatives (theta0 held), then the
    // chain rule: d theta0 / dp from one Newton step, d/d theta0 of each
    // integral by central differences (one Jet integral, not two).
    const double h = 1e-7 * std::max(root, 1e-3);
    const Integrals<double> plus = integrals<double>(pv, kv, w, o, s, root + h);
    const Integrals<double> minus = integrals<double>(pv, kv, w, o, s, root - h);
    const double dn = (plus.normal - minus.normal) / (2.0 * h);
    in = integrals<T>(p, slip_terms(p, w, o, s), w, o, s, theta0);
    theta0 = theta0 - (in.normal - load) / dn;
    const T step = theta0 - root;
    in.drawbar += (plus.drawbar - minus.drawbar) / (2.0 * h) * step;
    in.torque += (plus.torque - minus.torque) / (2.0 * h) * step;
    in.resistance += (plus.resistance - minus.resistance) / (2.0 * h) * step;
  } else {
    in = integrals<T>(p, kv, w, o, s, theta0);
  }
  out.status = TractionStatus::ok;
  out.theta0 = theta0;
  out.theta_m = theta0 * (p.c1 + p.c2 * s);
  out.sinkage = w.radius * (1.0 - cos(theta0));
  out.drawbar = in.drawbar;
  out.torque = in.torque;
  out.resistance = in.resistance;
  if (o.extensions.bulldozing) {
    const T bulldozing = p.bulldozing_scale * bulldozing_resistance(p, w.width, out.sinkage);
    out.drawbar -= bulldozing;
    out.resistance += bulldozing;
  }
  return out;
}

// Any slip in [-1, 1]: skid by anti-symmetry about the s = 0 value
// (Eq. 2.26-2.27, seed 003). Entry angle and sinkage of a skidding wheel are
// those of the mirrored slip.
// With a hint (model.h), each solve starts from it.
template <typename T>
Solution<T> solve_any_slip(const Params<T>& p, const Wheel& w, const ModelOptions& o, double s, double load,
                           EntryAngleHint* hint = nullptr) {
  double* entry = hint != nullptr ? &hint->entry : nullptr;
  if (s >= 0.0) return solve(p, w, o, s, load, entry);
  Solution<T> mirrored = solve(p, w, o, -s, load, entry);
  if (mirrored.status != TractionStatus::ok) return mirrored;
  Solution<T> zero = solve(p, w, o, 0.0, load, hint != nullptr ? &hint->zero_slip_entry : nullptr);
  if (zero.status != TractionStatus::ok) return zero;
  mirrored.drawbar = -mirrored.drawbar + 2.0 * zero.drawbar;  // Eq. 2.26
  mirrored.torque = -mirrored.torque + 2.0 * zero.torque;     // Eq. 2.27
  // The compaction resistance is that of the mirrored slip's sinkage (kept).
  return mirrored;
}

}  // namespace roverlab::terramechanics::detail
