#!/usr/bin/env python3
"""196-row single-wheel files at slip angles 0-90 deg, the shape of a real
slip-angle campaign (a wheel of r 62.5 mm and b 60 mm at 20 N, travel slips
-1..0.89 in steps of 0.07, slip angles 0-90 deg in steps of 15), from
`roverlab terramechanics` with a truth and Gaussian noise of the study's
stated sigmas (0.5 N, 0.5 N, 0.02 N m, 0.5 mm), seeded; the slip column is
`travel_slip` (stated), and `*_unstated.csv` copies name it `slip`.
Used by docs/terramechanics.md ("Model families") and docs/performance.md
("The RFT family") for the family step and the study's CPU.

  python3 tests/data/rft/make_slip_angle_files.py ROVERLAB OUTDIR
"""
import random
import sys

from make_study_files import B, R, noisy_rows  # the same wheel, noise and columns

SLIPS = [round(-1 + 0.07 * i, 3) for i in range(28)]
ANGLES = [0, 15, 30, 45, 60, 75, 90]
GROUSERS = ["--grousers", "12", "--grouser-height", "0.005"]
# name: (grousered, the truth's model arguments)
CASES = {
    "rft": (False, ["--model", "rft"]),
    "pile08": (False, ["--model", "rft+pile-up", "--pile-up", "0.8"]),
    "pile25": (False, ["--model", "rft+pile-up", "--pile-up", "2.5"]),
    "ishigami": (False, ["--model", "ishigami"]),
    "grousers13": (True, ["--model", "rft+grousers", "--grouser-effectiveness", "1.3"]),
}


def main():
    exe, out = sys.argv[1], sys.argv[2]
    for name, (grousered, args) in CASES.items():
        rng = random.Random(name)
        cmd = [exe, "terramechanics", "--soil", "dry_sand", "--radius", str(R), "--width", str(B),
               "--rft-scale", "2e6", "--slip-definition", "travel", "--load", "20",
               "--slip", ",".join(map(str, SLIPS)), "--slip-angle", ",".join(map(str, ANGLES))]
        cmd += (GROUSERS if grousered else []) + args
        lines = noisy_rows(cmd, grousered, rng)
        for suffix, slip in (("", "travel_slip"), ("_unstated", "slip")):
            with open("%s/slip_angle_%s%s.csv" % (out, name, suffix), "w") as f:
                f.write("wheel,grouser_count,grouser_height_m,radius_m,width_m,load_N,%s,slip_angle_deg,"
                        "drawbar_pull_N,lateral_force_N,torque_Nm,sinkage_m\n" % slip)
                f.writelines(lines)


if __name__ == "__main__":
    main()
