#!/usr/bin/env python3
"""Independent values for the peaked ("hump") shear curve of dense sand and
compact soils (Wong, Theory of Ground Vehicles, ch. 2; issue 33, item 4):

    tau = tau_max K_r [1 + (1 / (K_r (1 - 1/e)) - 1) exp(1 - j/K_w)] (1 - exp(-j/K_w))

with tau_max = c + sigma tan(phi), in the Wong-Reece wheel (seed 003
Eq. 2.10-2.24) in place of Eq. 2.19, K_w scaled by (1 + k_s s) as K is by
slip-shear-modulus. Written from the equations without RoverLab's C++ (the
formula as printed above, not the C++'s rearranged bracket): midpoint rule
with POINTS points over [0, theta_f], entry angle by bisection on F_z = W.

Rerun: python3 tests/data/single_wheel/shear_peak_reference.py
(plain Python 3, no packages). Prints the curve's checks and the rows
tests/core/terramechanics_model_test.cpp holds.
"""
import math

# ding_tyii (resources/soils/ding_tyii.json) and the Ding 2011 wheel.
N_EXP, C, PHI_DEG = 1.1, 250.0, 31.9
KC, KPHI, C1, C2 = 15600.0, 2407400.0, 0.18, 0.32
R, B = 0.15735, 0.165
POINTS = 500


def hump(j, k_r, k_w):
    """tau / tau_max, Wong's peaked curve as printed."""
    return k_r * (1 + (1 / (k_r * (1 - 1 / math.e)) - 1) * math.exp(1 - j / k_w)) * (1 - math.exp(-j / k_w))


def forces(theta_f, s, k_r, k_w, k_s):
    tan_phi = math.tan(math.radians(PHI_DEG))
    k = (KC + KPHI * B) * B ** (N_EXP - 1.0)
    theta_m = (C1 + C2 * s) * theta_f
    kw_s = k_w * (1.0 + k_s * s)
    fz = fx = torque = 0.0
    h = theta_f / POINTS
    for i in range(POINTS):
        th = (i + 0.5) * h
        eq = th if th >= theta_m else theta_f - th / theta_m * (theta_f - theta_m)
        arg = math.cos(eq) - math.cos(theta_f)
        sigma = k * (R / B * arg) ** N_EXP if arg > 0 else 0.0
        j = R * (theta_f - th - (1 - s) * (math.sin(theta_f) - math.sin(th)))
        tau = (C + sigma * tan_phi) * hump(j, k_r, kw_s)
        fz += R * B * (tau * math.sin(th) + sigma * math.cos(th)) * h
        fx += R * B * (tau * math.cos(th) - sigma * math.sin(th)) * h
        torque += R * R * B * tau * h
    return fz, fx, torque


def solve(w, s, k_r, k_w, k_s):
    lo, hi = 0.0, math.pi / 2
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        if forces(mid, s, k_r, k_w, k_s)[0] < w:
            lo = mid
        else:
            hi = mid
    th = 0.5 * (lo + hi)
    _, fx, tq = forces(th, s, k_r, k_w, k_s)
    return R * (1 - math.cos(th)), fx, tq


print("// curve checks: K_r, tau(K_w)/tau_max, tau(50 K_w)/tau_max, argmax j/K_w, max tau/tau_max")
for k_r in (0.3, 0.5, e_kr := math.e * (math.e - 2) / (math.e - 1) ** 2, 0.8, 1.0):
    xs = [i / 100000 for i in range(1, 500000)]
    x_max = max(xs, key=lambda x: hump(x, k_r, 1.0))
    print("//   %.4f: %.12f %.12f %.4f %.6f" % (k_r, hump(1.0, k_r, 1.0), hump(50.0, k_r, 1.0), x_max,
                                              hump(x_max, k_r, 1.0)))
print("// load, slip, K_r, K_w, k_s: sinkage_m, DP_N, torque_Nm")
for w, s, k_r, k_w, k_s in ((80.0, 0.1, 0.6, 0.008, 0.0), (80.0, 0.3, 0.6, 0.008, 0.0), (80.0, 0.6, 0.4, 0.004, 0.0),
                            (120.0, 0.2, 0.9, 0.02, 1.5), (40.0, 0.0, 0.7, 0.01, 0.0)):
    z, fx, tq = solve(w, s, k_r, k_w, k_s)
    print("{%.0f, %.1f, %.1f, %.3f, %.1f, %.9g, %.9g, %.9g}," % (w, s, k_r, k_w, k_s, z, fx, tq))
