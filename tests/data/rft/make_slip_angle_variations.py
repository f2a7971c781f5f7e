#!/usr/bin/env python3
"""Variations of the slip-angle files of make_slip_angle_files.py that were not
in the development set, to check the single-wheel study blind (issue 43):
other noise seeds of each development case, twice the noise, other pile-ups,
grouser height scales, loads and wheel size, Ishigami truths with a hidden
lateral shear modulus or sidewall scale, half the slips, and copies with
the slip unstated. Truth from `roverlab terramechanics`, noise and columns
as the development files (make_study_files.noisy_rows). Results:
docs/validation/slip-angle-variations.md.

  python3 tests/data/rft/make_slip_angle_variations.py ROVERLAB OUTDIR [--study] [--reuse]
      [--extra-seeds K [--seeds-of NAME,...]]

Writes OUTDIR/var_NAME.csv (slip stated, `travel_slip`), var_NAME_unstated.csv
(`slip`) for the cases in UNSTATED, and OUTDIR/truth.json (each file's truth).
With --study it then runs `ROVERLAB --threads 1 discrepancy single-wheel F
--soil dry_sand --json` on each file, one at a time (user CPU from
/usr/bin/time), keeps each JSON in OUTDIR/out/ and prints a Markdown table
(--reuse: a file whose JSON is already there is not studied again).
--extra-seeds K adds K more seeds (4, 5, ...) of pile08 and grousers13, or
of the cases and variations named by --seeds-of (sigma coverage).
"""
import argparse
import json
import os
import random
import subprocess
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


def variations(extra_seeds=0, seeds_of=("pile08", "grousers13")):
    """name -> dict(base case of make_slip_angle_files.CASES or own args, changes); extra_seeds more
    seeds (4, 5, ...) of each case or variation named in seeds_of."""
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
    for case in seeds_of:
        for k in range(4, 4 + extra_seeds):
            v["%s_seed%d" % (case, k)] = v.get(case, {"base": case})
    return v


UNSTATED = ["pile08_seed1", "grousers13_seed1", "ishigami_sidewall3"]


def write_atomic(path, text):
    with open(path + ".tmp", "w") as f:
        f.write(text)
    os.replace(path + ".tmp", path)


def write(path, lines, slip):
    write_atomic(path, "wheel,grouser_count,grouser_height_m,radius_m,width_m,load_N,%s,slip_angle_deg,"
                 "drawbar_pull_N,lateral_force_N,torque_Nm,sinkage_m\n" % slip + "".join(lines))


def generate(exe, out, extra_seeds, seeds_of):
    os.makedirs(out, exist_ok=True)
    with open(DRY_SAND) as f:
        soil = json.load(f)
    soil["name"], soil["lateral_shear_modulus_m"] = "dry_sand_ky", K_Y
    soil_ky = os.path.join(out, "dry_sand_ky.json")
    write_atomic(soil_ky, json.dumps(soil))
    truth = {}
    for name, c in variations(extra_seeds, seeds_of).items():
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
    write_atomic(os.path.join(out, "truth.json"), json.dumps(truth, indent=1))


# name prefix -> (family, the candidate that is the hidden change, its parameter, its truth)
TRUTH = [("rft_", "RFT", "", "", None), ("pile08", "RFT", "pile-up", "rft_pileup", 0.8),
         ("pile10", "RFT", "pile-up", "rft_pileup", 1.0), ("pile15", "RFT", "pile-up", "rft_pileup", 1.5),
         ("pile25", "RFT", "pile-up", "rft_pileup", 2.5), ("pile30", "RFT", "pile-up", "rft_pileup", 3.0),
         ("grousers08", "RFT", "grousers", "grouser_effectiveness", 0.8),
         ("grousers13", "RFT", "grousers", "grouser_effectiveness", 1.3),
         ("grousers16", "RFT", "grousers", "grouser_effectiveness", 1.6),
         ("ishigami_ky", "Ishigami", "lateral-shear-modulus", "lateral_shear_modulus", K_Y),
         ("ishigami_sidewall3", "Ishigami", "sidewall", "sidewall_scale", 3.0),
         ("ishigami_seed", "Ishigami", "", "", None)]


def truth_of(name):
    return next(t[1:] for t in TRUTH if name.startswith(t[0]))


def summary(d, name):
    """One reading's row: family, chain, named causes, hidden parameter vs truth, bounds, held-out F_y, DP."""
    family, cand, param, value = truth_of(name)
    final = d["selection"][-1] if d["selection"] else None
    params = final["parameters"] if final else next(
        (f["parameters"] for f in d["families"] if d["family_choice"].startswith("family " + f["family"])), [])
    rmse = final["held_out_rmse"] if final else d["baseline"]["held_out_rmse"]
    fam = "RFT" if d["baseline_model"].startswith("RFT") else "Ishigami"
    fitted = next((p for p in params if p["name"] == param), None)
    zeta = next((p for p in params if p["name"] == "rft_scale"), None)
    cause = d["cause"] or ""  # named: the causes, not steps "also consistent with"
    chain = "" if d["final_model"] == "baseline" else d["final_model"]
    exact = fam == family and cause == cand
    within = None
    if fitted and not fitted["at_bound"] and fitted["sigma"] > 0:
        within = abs(fitted["value"] - value) / fitted["sigma"]
    return {"family": fam, "chain": chain or "-", "cause": cause or "-", "exact": exact,
            "fitted": fitted, "truth": value, "z": within, "zeta": zeta,
            "zeta_z": abs(zeta["value"] - 2e6) / zeta["sigma"] if zeta and zeta["sigma"] > 0 else None,
            "at_bound": [p["name"] for p in params if p["at_bound"]],
            "roles": [s["role"] for s in d["selection"]],
            "fy": rmse.get("lateral_force"), "dp": rmse.get("drawbar_pull"),
            "slip_definition": d["slip_definition"], "choice": d["family_choice"]}


def study(exe, out, reuse):
    os.makedirs(os.path.join(out, "out"), exist_ok=True)
    rows = []
    for f in sorted(x for x in os.listdir(out) if x.startswith("var_") and x.endswith(".csv")):
        name = f[4:-4]
        res = os.path.join(out, "out", name + ".json")
        tfile = os.path.join(out, "out", name + ".time")
        if not (reuse and os.path.exists(res) and os.path.exists(tfile)):
            run = subprocess.run(["/usr/bin/time", "-f", "%U", "-o", tfile, "nice", "-n", "5", exe, "--threads", "1",
                                  "discrepancy", "single-wheel", os.path.join(out, f), "--soil", "dry_sand",
                                  "--json"], stdout=subprocess.PIPE, text=True, check=True)
            write_atomic(res, run.stdout)
        with open(tfile) as t:
            cpu = float(t.read().split()[-1])
        with open(res) as r:
            d = json.load(r)
        readings = [d] + ([d["other_reading"]] if "other_reading" in d else [])
        for r in readings:
            s = summary(r, name.replace("_unstated", ""))
            s.update(name=name, cpu=cpu, first=r is d)
            rows.append(s)
            print(json.dumps(s), file=sys.stderr)
    write_atomic(os.path.join(out, "summary.json"), json.dumps(rows, indent=1))
    return rows


def fmt(p):
    return "-" if p is None else ("%.4g at its bound" % p["value"] if p["at_bound"] else
                                  "%.4g +- %.2g" % (p["value"], p["sigma"]))


def table(rows):
    print("| file | slip read | family | chain | hidden: fitted (truth) | within 2 sigma | zeta (2e6) | at bound "
          "| held-out F_y, DP (N) | CPU s |")
    print("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |")
    for s in rows:
        z = "-" if s["z"] is None else ("yes (%.1f)" % s["z"] if s["z"] <= 2 else "**no (%.1f)**" % s["z"])
        hidden = "-" if s["truth"] is None else "%s (%g)" % (fmt(s["fitted"]), s["truth"])
        zeta = "-" if s["zeta"] is None else "%.3g +- %.1g (%.1f)" % (
            s["zeta"]["value"], s["zeta"]["sigma"], s["zeta_z"] or 0)
        print("| %s | %s%s | %s | %s | %s | %s | %s | %s | %.2f, %.2f | %s |" % (
            s["name"], s["slip_definition"], "" if s["first"] else " (2nd)", s["family"],
            s["chain"] + ("" if s["cause"] == s["chain"] else " (named: %s)" % s["cause"]) + ("" if s["exact"] else " **x**"), hidden, z, zeta, ", ".join(s["at_bound"]) or "-",
            s["fy"], s["dp"], "%.1f" % s["cpu"] if s["first"] else ""))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("roverlab")
    ap.add_argument("outdir")
    ap.add_argument("--study", action="store_true")
    ap.add_argument("--extra-seeds", type=int, default=0)
    ap.add_argument("--seeds-of", default="pile08,grousers13")
    ap.add_argument("--reuse", action="store_true")
    a = ap.parse_args()
    generate(a.roverlab, a.outdir, a.extra_seeds, a.seeds_of.split(","))
    if a.study:
        table(study(a.roverlab, a.outdir, a.reuse))


if __name__ == "__main__":
    main()
