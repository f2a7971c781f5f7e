#!/usr/bin/env python3
"""Independent values for the drawbar-pull extensions of issue 33 (item 4):
Wong-Reece (seed 003 Eq. 2.10-2.24) with a rear contact angle
theta_r = -kappa theta_f (Wong & Reece 1967; Ishigami et al. 2007 Eq. 6) and a
slip-dependent shear deformation modulus K = K0 (1 + k_s s) (Ding et al.
2015), written from the equations without RoverLab's C++: midpoint rule with
POINTS points over [theta_r, theta_f], entry angle by bisection on F_z = W.

Rerun: python3 tests/data/single_wheel/extensions_reference.py
(plain Python 3, no packages). Prints the rows
tests/core/terramechanics_model_test.cpp holds.
"""
import math

# ding_tyii (resources/soils/ding_tyii.json) and the Ding 2011 wheel.
N_EXP, C, PHI_DEG, K0 = 1.1, 250.0, 31.9, 0.0114
KC, KPHI, C1, C2 = 15600.0, 2407400.0, 0.18, 0.32
R, B = 0.15735, 0.165
POINTS = 500


def forces(theta_f, s, kappa, k_s):
    tan_phi = math.tan(math.radians(PHI_DEG))
    k = (KC + KPHI * B) * B ** (N_EXP - 1.0)
    theta_m = (C1 + C2 * s) * theta_f
    theta_r = -kappa * theta_f
    shear_k = K0 * (1.0 + k_s * s)
    fz = fx = torque = 0.0
    h = (theta_f - theta_r) / POINTS
    for i in range(POINTS):
        th = theta_r + (i + 0.5) * h
        if th >= theta_m:
            eq = th
        else:  # rear zone, from theta_r (no stress) up to theta_m
            eq = theta_f - (th - theta_r) / (theta_m - theta_r) * (theta_f - theta_m)
        arg = math.cos(eq) - math.cos(theta_f)
        sigma = k * (R / B * arg) ** N_EXP if arg > 0 else 0.0
        j = R * (theta_f - th - (1 - s) * (math.sin(theta_f) - math.sin(th)))
        tau = (C + sigma * tan_phi) * (1 - math.exp(-j / shear_k))
        fz += R * B * (tau * math.sin(th) + sigma * math.cos(th)) * h
        fx += R * B * (tau * math.cos(th) - sigma * math.sin(th)) * h
        torque += R * R * B * tau * h
    return fz, fx, torque


def solve(w, s, kappa, k_s):
    lo, hi = 0.0, math.pi / 2
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        if forces(mid, s, kappa, k_s)[0] < w:
            lo = mid
        else:
            hi = mid
    th = 0.5 * (lo + hi)
    _, fx, tq = forces(th, s, kappa, k_s)
    return R * (1 - math.cos(th)), fx, tq


print("// load, slip, kappa, k_s: sinkage_m, DP_N, torque_Nm")
for w, s, kappa, k_s in ((80.0, 0.3, 0.0, 0.0), (80.0, 0.3, 0.25, 0.0), (80.0, 0.1, 0.0, 3.0), (120.0, 0.6, 0.4, 1.5),
                         (40.0, 0.0, 0.2, 2.0)):
    z, fx, tq = solve(w, s, kappa, k_s)
    print("{%.0f, %.1f, %.2f, %.1f, %.9g, %.9g, %.9g}," % (w, s, kappa, k_s, z, fx, tq))
