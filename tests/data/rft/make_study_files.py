#!/usr/bin/env python3
"""RFT-generated single-wheel files with one hidden change, for the study.

Each file: one wheel (r 62.5 mm, b 60 mm; smooth, or 12 grousers of 5 mm as
the file states), load 20 N, slip angles 0-90 deg in steps of 15, travel slips
-0.6..0.8, drawbar pull, lateral force, torque and sinkage from
`roverlab terramechanics --model rft` with the truth's options, plus Gaussian
noise of the study's stated sigmas (0.5 N, 0.5 N, 0.02 N m, 0.5 mm), seeded;
rft_depth1_loads.csv the depth-scale case at 10, 20 and 40 N.

  python3 tests/data/rft/make_study_files.py ROVERLAB OUTDIR
"""
import random
import subprocess
import sys

R, B, ZETA = 0.0625, 0.06, 2.0e6
SLIPS = [-0.6, -0.3, 0.0, 0.2, 0.4, 0.6, 0.8]
ANGLES = [0, 15, 30, 45, 60, 75, 90]
# name: (grousers in the file, truth's extra CLI arguments)
CASES = {
    "none": (False, ["--model", "rft"]),
    "zeta3e6": (False, ["--model", "rft", "--rft-scale", "3e6"]),
    "pileup05": (False, ["--model", "rft+pile-up", "--pile-up", "0.5"]),
    "depth1": (False, ["--model", "rft+depth-scale", "--depth-scale", "1"]),
    "grousers_none": (True, ["--model", "rft"]),
    "grouser_height13": (True, ["--model", "rft+grousers", "--grouser-effectiveness", "1.3"]),
}
LOADS = {"depth1_loads": "10,20,40"}  # files at several loads (default 20 N)
CASES["depth1_loads"] = CASES["depth1"]


def noisy_rows(cmd, grousered, rng):
    """The rows `roverlab terramechanics` (cmd) computes, status ok, as CSV lines
    (wheel, grousers, radius, width, load, slip, slip angle, then drawbar pull,
    lateral force, torque and sinkage with the study's stated noise)."""
    rows = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout.splitlines()
    header = rows[0].split(",")
    lines = []
    for line in rows[1:]:
        r = dict(zip(header, line.split(",")))
        if r["status"] != "ok":
            continue
        lines.append("%s,%d,%g,%g,%g,%s,%s,%s,%.4f,%.4f,%.5f,%.6f\n" % (
            "grousered" if grousered else "smooth", 12 if grousered else 0, 0.005 if grousered else 0.0,
            R, B, r["load_N"], r["slip"], r["slip_angle_deg"],
            float(r["drawbar_pull_N"]) + rng.gauss(0, 0.5), float(r["lateral_force_N"]) + rng.gauss(0, 0.5),
            float(r["resistive_torque_Nm"]) + rng.gauss(0, 0.02), float(r["sinkage_m"]) + rng.gauss(0, 0.0005)))
    return lines


def main():
    exe, out = sys.argv[1], sys.argv[2]
    for name, (grousered, args) in CASES.items():
        rng = random.Random(name)
        wheel = ["--grousers", "12", "--grouser-height", "0.005"] if grousered else []
        zeta = [] if "--rft-scale" in args else ["--rft-scale", str(ZETA)]
        cmd = [exe, "terramechanics", "--soil", "dry_sand", "--radius", str(R), "--width", str(B)] + zeta + [
               "--slip-definition", "travel", "--load", LOADS.get(name, "20"), "--slip", ",".join(map(str, SLIPS)),
               "--slip-angle", ",".join(map(str, ANGLES))] + wheel + args
        with open("%s/rft_%s.csv" % (out, name), "w") as f:
            f.write("wheel,grouser_count,grouser_height_m,radius_m,width_m,load_N,slip,slip_angle_deg,"
                    "drawbar_pull_N,lateral_force_N,torque_Nm,sinkage_m\n")
            f.writelines(noisy_rows(cmd, grousered, rng))

if __name__ == "__main__":
    main()
