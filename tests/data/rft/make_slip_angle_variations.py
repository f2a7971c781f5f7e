#!/usr/bin/env python3
"""Variations of the slip-angle files of make_slip_angle_files.py that were not
in the development set, to check the single-wheel study blind (issue 43):
other noise seeds of each development case, twice the noise, other pile-ups,
grouser height scales, loads and wheel size, Ishigami truths with a hidden
lateral shear modulus or sidewall scale, half the slips, and copies with
the slip unstated. Truth from `roverlab terramechanics`, noise and columns
as the development files (make_study_files.noisy_rows). Results:
docs/validation/slip-angle-variations.md.

  python3 tests/data/rft/make_slip_angle_variations.py ROVERLAB OUTDIR

Writes OUTDIR/var_NAME.csv (slip stated, `travel_slip`), var_NAME_unstated.csv
(`slip`) for the cases in UNSTATED, and OUTDIR/truth.json (each file's truth).
"""
import json
import os
import random
import sys

import make_study_files
from make_slip_angle_files import ANGLES, CASES, GROUSERS, SLIPS

HERE = os.path.dirname(os.path.abspath(__file__))
DRY_SAND = os.path.join(HERE, "..", "..", "..", "resources", "soils", "dry_sand.json")
SLIPS_COARSE = [round(-1 + 0.14 * i, 3) for i in range(14)]  # -1..0.82, 98 rows
K_Y = 0.035  # hidden lateral shear modulus, m (dry_sand's K_s is 0.0175)


class ScaledNoise:
    """A random.Random whose Gaussian draws have k times the asked sigma."""

    def __init__(self, rng, k):
        self.rng, self.k = rng, k

    def gauss(self, mu, sigma):
        return self.rng.gauss(mu, sigma * self.k)


def variations():
    """name -> dict(base case of make_slip_angle_files.CASES or own args, changes)."""
    v = {}
    for base in CASES:
        for k in (1, 2, 3):
            v["%s_seed%d" % (base, k)] = {"base": base}
    v["rft_noise2"] = {"base": "rft", "noise": 2}
    v["pile08_noise2"] = {"base": "pile08", "noise": 2}
    v["grousers13_noise2"] = {"base": "grousers13", "noise": 2}
    v["pile15"] = {"grousered": False, "args": ["--model", "rft+pile-up", "--pile-up", "1.5"]}
    # The CLI's truth stops at a pile-up of 3 (the study's bound is 10): 4.0 cannot be generated.
    v["pile30"] = {"grousered": False, "args": ["--model", "rft+pile-up", "--pile-up", "3.0"]}
    v["grousers08"] = {"grousered": True, "args": ["--model", "rft+grousers", "--grouser-effectiveness", "0.8"]}
    v["grousers16"] = {"grousered": True, "args": ["--model", "rft+grousers", "--grouser-effectiveness", "1.6"]}
    v["pile08_load15"] = {"base": "pile08", "load": 15}
    v["grousers13_load30"] = {"base": "grousers13", "load": 30}
    v["pile10_r80b100"] = {"grousered": False, "args": ["--model", "rft+pile-up", "--pile-up", "1.0"],
                           "wheel": (0.08, 0.1)}
    v["ishigami_ky035"] = {"grousered": False, "args": ["--model", "ishigami"], "k_y": K_Y}
    v["ishigami_sidewall3"] = {"grousered": False, "args": ["--model", "ishigami", "--sidewall-scale", "3"]}
    v["pile25_coarse"] = {"base": "pile25", "slips": SLIPS_COARSE}
    return v


UNSTATED = ["pile08_seed1", "grousers13_seed1", "ishigami_sidewall3"]


def write(path, lines, slip):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("wheel,grouser_count,grouser_height_m,radius_m,width_m,load_N,%s,slip_angle_deg,"
                "drawbar_pull_N,lateral_force_N,torque_Nm,sinkage_m\n" % slip)
        f.writelines(lines)
    os.replace(tmp, path)


def main():
    exe, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    with open(DRY_SAND) as f:
        soil = json.load(f)
    soil["name"], soil["lateral_shear_modulus_m"] = "dry_sand_ky", K_Y
    soil_ky = os.path.join(out, "dry_sand_ky.json")
    with open(soil_ky, "w") as f:
        json.dump(soil, f)
    truth = {}
    for name, c in variations().items():
        grousered, args = CASES[c["base"]] if "base" in c else (c["grousered"], c["args"])
        r, b = c.get("wheel", (make_study_files.R, make_study_files.B))
        rng = random.Random("variation/" + name)
        cmd = [exe, "terramechanics", "--soil", soil_ky if "k_y" in c else "dry_sand", "--radius", str(r),
               "--width", str(b), "--rft-scale", "2e6", "--slip-definition", "travel",
               "--load", str(c.get("load", 20)), "--slip", ",".join(map(str, c.get("slips", SLIPS))),
               "--slip-angle", ",".join(map(str, ANGLES))] + (GROUSERS if grousered else []) + args
        saved = make_study_files.R, make_study_files.B
        make_study_files.R, make_study_files.B = r, b  # noisy_rows writes the wheel's geometry from these
        try:
            lines = make_study_files.noisy_rows(cmd, grousered, ScaledNoise(rng, c.get("noise", 1)))
        finally:
            make_study_files.R, make_study_files.B = saved
        truth[name] = {"args": args + (["lateral_shear_modulus_m", K_Y] if "k_y" in c else []),
                       "grousered": grousered, "rows": len(lines), "noise": c.get("noise", 1)}
        write("%s/var_%s.csv" % (out, name), lines, "travel_slip")
        if name in UNSTATED:
            write("%s/var_%s_unstated.csv" % (out, name), lines, "slip")
    with open(os.path.join(out, "truth.json"), "w") as f:
        json.dump(truth, f, indent=1)


if __name__ == "__main__":
    main()
