#!/usr/bin/env python3
"""Independent values of the RFT wheel model (core/terramechanics/rft.h).

Written from the equations, without RoverLab's C++: Li, Zhang and Goldman
2013 (Science 339:1408) generic alpha_x, alpha_z Fourier fit evaluated with
trigonometric calls on the angles beta, gamma (the C++ uses double-angle
algebra); each surface element taken in the vertical plane of its velocity
(after Treers et al. 2021), only leading elements below the free surface;
the sinkage by plain bisection on the summed vertical force (the C++ uses
prefix sums over sorted immersion depths). The mesh is rebuilt here from
the rule rft.h states (rim 90 x 8, side faces 90 x 6 each over the lower
half, grousers with front, back and tip faces at 4 phases a pitch).

Run:   python3 tests/data/rft/rft_reference.py            (prints the rows)
Check: python3 tests/data/rft/rft_reference.py --roverlab build/app/roverlab
       (runs `roverlab terramechanics --model rft ...` on the same points and
       exits 1 when a value differs by more than 1e-6 relative + 1e-9)
Plain Python 3, no packages.
"""
import math
import subprocess
import sys

A00, A10, B11, B01, BM11 = 0.206, 0.169, 0.212, 0.358, 0.055
C11, C01, CM11, D10 = -0.124, 0.253, 0.007, 0.088
ANGLES, ACROSS, RINGS, GROUSER_ROWS, PHASES = 90, 8, 6, 2, 4


def alpha(beta, gamma):
    """Li 2013 Eq. S2 (m in -1..1, n in 0..1), (alpha_x, alpha_z)."""
    az = (A00 + A10 * math.cos(2 * beta) + B11 * math.sin(2 * beta + gamma) + B01 * math.sin(gamma)
          + BM11 * math.sin(-2 * beta + gamma))
    ax = (C11 * math.cos(2 * beta + gamma) + C01 * math.cos(gamma) + CM11 * math.cos(-2 * beta + gamma)
          + D10 * math.sin(2 * beta))
    return ax, az


def mesh(r, b, count=0, height=0.0, thickness=0.0):
    """(position, outward normal, area, part) of each element."""
    out = []
    dth = math.pi / ANGLES
    for i in range(ANGLES):
        th = -math.pi / 2 + (i + 0.5) * dth
        for k in range(ACROSS):
            y = -b / 2 + (k + 0.5) * b / ACROSS
            out.append(((r * math.sin(th), y, -r * math.cos(th)), (math.sin(th), 0.0, -math.cos(th)),
                        r * dth * b / ACROSS, "rim"))
    for side in (-1, 1):
        for i in range(ANGLES):
            th = -math.pi / 2 + (i + 0.5) * dth
            for k in range(RINGS):
                rho = (k + 0.5) * r / RINGS
                out.append(((rho * math.sin(th), side * b / 2, -rho * math.cos(th)), (0.0, float(side), 0.0),
                            rho * (r / RINGS) * dth, "side"))
    if count > 0 and height > 0:
        pitch = 2 * math.pi / count
        for g in range(count):
            for p in range(PHASES):
                th = math.remainder(g * pitch + (p + 0.5) * pitch / PHASES, 2 * math.pi)
                if abs(th) > math.pi / 2:
                    continue
                for face in (-1, 1):
                    a = th + face * thickness / (2 * r)
                    for j in range(GROUSER_ROWS):
                        rho = r + (j + 0.5) * height / GROUSER_ROWS
                        for k in range(ACROSS):
                            y = -b / 2 + (k + 0.5) * b / ACROSS
                            out.append(((rho * math.sin(a), y, -rho * math.cos(a)),
                                        (face * math.cos(a), 0.0, face * math.sin(a)),
                                        height / GROUSER_ROWS * b / ACROSS / PHASES, "grouser"))
                if thickness > 0:
                    for k in range(ACROSS):
                        y = -b / 2 + (k + 0.5) * b / ACROSS
                        out.append((((r + height) * math.sin(th), y, -(r + height) * math.cos(th)),
                                    (math.sin(th), 0.0, -math.cos(th)), thickness * b / ACROSS / PHASES, "grouser"))
    return out


def stress(n, u):
    """Soil force per unit zeta and depth on a unit-area element."""
    speed = math.sqrt(sum(c * c for c in u))
    if speed == 0 or not sum(a * c for a, c in zip(n, u)) > 0:  # leading elements only
        return (0.0, 0.0, 0.0)
    h = math.hypot(u[0], u[1])
    if h > 1e-9 * speed:
        rdir = (u[0] / h, u[1] / h)
    else:
        hn = math.hypot(n[0], n[1])
        rdir = (n[0] / hn, n[1] / hn) if hn > 1e-12 else (1.0, 0.0)
    tdir = (-rdir[1], rdir[0])
    gamma = math.atan2(-u[2], u[0] * rdir[0] + u[1] * rdir[1])  # below the horizontal
    n_r, n_t, n_z = n[0] * rdir[0] + n[1] * rdir[1], n[0] * tdir[0] + n[1] * tdir[1], n[2]
    length = math.hypot(n_r, n_z)
    if length < 1e-12:
        return (0.0, 0.0, 0.0)
    beta = math.atan(-n_r / n_z) if n_z != 0 else math.pi / 2  # the element's angle in the plane
    ax, az = alpha(beta, gamma)
    f_r, f_z = -ax * length, az * length
    pressure = (ax * n_r - az * n_z) / length  # -(a . n'), per unit projected area
    f_t = -pressure * length * n_t
    return (f_r * rdir[0] + f_t * tdir[0], f_r * rdir[1] + f_t * tdir[1], f_z)


def motion(slip, beta, travel):
    """Centre velocity and r w for the slip reading; 90 deg as the limit from below."""
    c = max(math.cos(beta), 1e-6)
    if travel:
        return ((1 - slip) * c, (1 - slip) * math.sin(beta), 0.0), 1.0
    return ((1 - slip) * c, (1 - slip) * math.sin(beta), 0.0), c


def evaluate(r, b, zeta, load, slip, beta_deg, travel, grousers=(0, 0.0, 0.0), pileup=0.0, depth_scale=0.0):
    beta = math.radians(beta_deg)
    centre, rim_speed = motion(slip, beta, travel)
    omega = rim_speed / r
    elements = []
    for p, n, area, part in mesh(r, b, *grousers):
        u = (centre[0] + omega * p[2], centre[1], centre[2] - omega * p[0])  # v_c + w y x p
        f = stress(n, u)
        if f == (0.0, 0.0, 0.0):
            continue
        h = math.hypot(u[0], u[1])
        push = max(0.0, (n[0] * u[0] + n[1] * u[1]) / h) if h > 0 else 0.0
        elements.append((p, tuple(zeta * area * c for c in f), p[2] + r, 1 + pileup * push, part))

    def totals(s):
        fx = fy = fz = torque = side = 0.0
        for p, f, z, m, part in elements:
            d = m * s - z
            if d <= 0:
                continue
            g = d * (1 + depth_scale * d / r)
            fx += f[0] * g
            fy += f[1] * g
            fz += f[2] * g
            torque += p[0] * f[2] * g - p[2] * f[0] * g
            side += f[1] * g if part == "side" else 0.0
        return fx, fy, fz, torque, side

    lo = min(z / m for _, _, z, m, _ in elements)
    hi = r
    if totals(hi)[2] < load:
        return None
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if totals(mid)[2] < load:
            lo = mid
        else:
            hi = mid
    s = 0.5 * (lo + hi)
    fx, fy, fz, torque, side = totals(s)
    return {"drawbar_pull_N": fx, "lateral_force_N": fy, "resistive_torque_Nm": torque, "sinkage_m": s,
            "sidewall_force_N": side}


R, B, ZETA = 0.0625, 0.06, 2.0e6
# (name, CLI arguments, python keyword arguments, loads, slips, slip angles)
CASES = [
    ("smooth travel", ["--model", "rft", "--slip-definition", "travel"], {"travel": True},
     [20.0], [-0.5, 0.0, 0.3, 0.8], [0.0, 30.0, 60.0, 90.0]),
    ("grousered longitudinal", ["--model", "rft", "--grousers", "12", "--grouser-height", "0.005",
                                "--grouser-thickness", "0.002"], {"travel": False, "grousers": (12, 0.005, 0.002)},
     [10.0, 40.0], [0.2, 0.6], [0.0, 45.0]),
    ("smooth travel, pile-up 0.5 and depth scale 1", ["--model", "rft+pile-up+depth-scale", "--pile-up", "0.5",
                                                      "--depth-scale", "1", "--slip-definition", "travel"],
     {"travel": True, "pileup": 0.5, "depth_scale": 1.0}, [20.0], [-0.8, 0.1, 0.5], [15.0, 75.0]),
]
COLUMNS = ["drawbar_pull_N", "lateral_force_N", "resistive_torque_Nm", "sinkage_m", "sidewall_force_N"]


def reference_rows():
    for name, args, kwargs, loads, slips, angles in CASES:
        for load in loads:
            for slip in slips:
                for angle in angles:
                    yield name, args, load, slip, angle, evaluate(R, B, ZETA, load, slip, angle, **kwargs)


def roverlab_rows(exe, args, loads, slips, angles):
    cmd = [exe, "terramechanics", "--soil", "dry_sand", "--radius", str(R), "--width", str(B), "--rft-scale",
           str(ZETA), "--load", ",".join(map(str, loads)), "--slip", ",".join(map(str, slips)), "--slip-angle",
           ",".join(map(str, angles))] + args
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout.splitlines()
    header = out[0].split(",")
    return [dict(zip(header, line.split(","))) for line in out[1:]]


def main():
    exe = sys.argv[sys.argv.index("--roverlab") + 1] if "--roverlab" in sys.argv else None
    failures = checked = 0
    cli = {}
    for name, args, loads, slips, angles in ((c[0], c[1], c[3], c[4], c[5]) for c in CASES):
        if exe:
            cli[name] = iter(roverlab_rows(exe, args, loads, slips, angles))
    for name, _, load, slip, angle, ref in reference_rows():
        text = "%s W=%g s=%g beta=%g: " % (name, load, slip, angle)
        text += "unsupported" if ref is None else " ".join("%s=%.9g" % (c, ref[c]) for c in COLUMNS)
        print(text)
        if not exe:
            continue
        row = next(cli[name])
        if ref is None:
            ok = row["status"] != "ok"
        else:
            ok = row["status"] == "ok" and all(
                abs(float(row[c]) - ref[c]) <= 1e-6 * abs(ref[c]) + 1e-9 for c in COLUMNS)
        checked += 1
        if not ok:
            failures += 1
            print("  MISMATCH roverlab:", row)
    if exe:
        print("%d of %d points agree" % (checked - failures, checked))
        return 1 if failures or checked == 0 else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())
