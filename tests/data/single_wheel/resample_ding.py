#!/usr/bin/env python3
"""Resampled Ding 2011 rows (issue 29's example, docs/validation/terramechanics.md):
the 12 measured rows repeated to ROWS, each with a load drawn in 60-100 N and
3 % Gaussian noise on drawbar pull, torque and sinkage.

Usage: python3 tests/data/single_wheel/resample_ding.py SEED ROWS > OUT.csv
"""
import csv
import os
import random
import sys

seed, count = int(sys.argv[1]), int(sys.argv[2])
here = os.path.dirname(os.path.abspath(__file__))
rows = list(csv.DictReader(open(os.path.join(here, "ding2011_tyii.csv"))))
random.seed(seed)
out = csv.DictWriter(sys.stdout, fieldnames=rows[0].keys(), lineterminator="\n")
out.writeheader()
for i in range(count):
    r = dict(rows[i % len(rows)])
    r["load_N"] = "%.3f" % random.uniform(60, 100)
    for k in ("drawbar_pull_N", "torque_Nm", "sinkage_m"):
        if r[k] != "":
            r[k] = "%.6g" % (float(r[k]) * random.gauss(1, 0.03))
    out.writerow(r)
