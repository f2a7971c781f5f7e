#!/usr/bin/env python3
"""Independent values for tests/core/slip_angle_model_test.cpp.

A rigid wheel at a slip angle (Ishigami et al. 2007, J. Field Robotics
24(3), Eq. 3-12, with Wong-Reece's normal stress of seed 003 Eq. 2.11-2.14)
written from the equations, without RoverLab's C++: midpoint rule with N
points over [0, theta_f], entry angle by bisection on F_z = W.

Rerun: python3 tests/data/slip_angle/ishigami_reference.py
(plain Python 3, no packages). Prints the rows the test holds.
"""
import math

# ding_tyii (resources/soils/ding_tyii.json) and the Kapvik wheel.
N_EXP, C, PHI_DEG, KX = 1.1, 250.0, 31.9, 0.0114
KC, KPHI, A0, A1, RHO = 15600.0, 2407400.0, 0.18, 0.32, 1600.0
R, B = 0.075, 0.07
G = 9.80665
POINTS = 400


def forces(theta_f, s, beta, k_y, shared):
    tan_phi = math.tan(math.radians(PHI_DEG))
    k = (KC + KPHI * B) * B ** (N_EXP - 1.0)
    theta_m = (A0 + A1 * s) * theta_f
    phi = math.atan(tan_phi)
    xc = math.pi / 4 - phi / 2
    d1 = 1 / math.tan(xc) + math.tan(xc + phi)
    d2 = 1 / math.tan(xc) + (1 / math.tan(xc)) ** 2 / (1 / tan_phi)
    fz = fx = torque = fy_shear = fy_side = 0.0
    h = theta_f / POINTS
    for i in range(POINTS):
        th = (i + 0.5) * h
        if th >= theta_m:
            arg = math.cos(th) - math.cos(theta_f)
        else:
            arg = math.cos(theta_f - th / theta_m * (theta_f - theta_m)) - math.cos(theta_f)
        sigma = k * (R / B * arg) ** N_EXP if arg > 0 else 0.0
        tmax = C + sigma * tan_phi
        jx = R * (theta_f - th - (1 - s) * (math.sin(theta_f) - math.sin(th)))
        jy = R * (1 - s) * (theta_f - th) * math.tan(beta)
        if shared:
            u, v = jx / KX, jy / k_y
            mag = math.sqrt(u * u + v * v)
            t = tmax * (1 - math.exp(-mag))
            tx, ty = (t * u / mag, t * v / mag) if mag > 0 else (0.0, 0.0)
        else:
            tx = tmax * (1 - math.exp(-jx / KX))
            ty = math.copysign(tmax * (1 - math.exp(-abs(jy) / k_y)), jy)
        fz += R * B * (tx * math.sin(th) + sigma * math.cos(th)) * h
        fx += R * B * (tx * math.cos(th) - sigma * math.sin(th)) * h
        torque += R * R * B * tx * h
        fy_shear += R * B * ty * h
        depth = R * (math.cos(th) - math.cos(theta_f))
        rb = d1 * (C * depth + d2 * RHO * G * depth * depth / 2) if depth > 0 else 0.0
        fy_side += rb * (R - depth * math.cos(th)) * h
    sign = (beta > 0) - (beta < 0)
    return fz, fx, torque, -fy_shear, -sign * fy_side


def solve(w, s, beta, k_y, shared):
    lo, hi = 0.0, math.pi / 2
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if forces(mid, s, beta, k_y, shared)[0] < w:
            lo = mid
        else:
            hi = mid
    th = 0.5 * (lo + hi)
    _, fx, torque, fy_shear, fy_side = forces(th, s, beta, k_y, shared)
    return R * (1 - math.cos(th)), fx, torque, fy_shear + fy_side, fy_side


print("// shared, k_y, load, slip, beta_deg: sinkage_m, DP_N, torque_Nm, Fy_N, sidewall_N")
for shared in (True, False):
    for k_y in (KX, 0.02):
        for w, s, beta_deg in ((50.0, 0.2, 0.0), (50.0, 0.2, 10.0), (50.0, 0.2, 30.0), (100.0, 0.5, -20.0),
                               (30.0, 0.0, 60.0)):
            z, fx, tq, fy, side = solve(w, s, math.radians(beta_deg), k_y, shared)
            print("{%s, %.4f, %.0f, %.1f, %.0f, %.9g, %.9g, %.9g, %.9g, %.9g}," %
                  ("true" if shared else "false", k_y, w, s, beta_deg, z, fx, tq, fy, side))
