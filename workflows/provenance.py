#!/usr/bin/env python3
"""Writes runs/NAME/run.json for workflows/Snakefile's provenance step.

What produced a run's numbers: the RoverLab version, the commands as run,
the seed, the injected effects, and the sha256 of every input file. No
dates, so the same campaign run twice writes the same file.

Usage: provenance.py ITEMS_JSON NAME OUTPUT COMMAND...
"""
import hashlib
import json
import os
import sys


def sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def main():
    items_file, name, output = sys.argv[1:4]
    commands = sys.argv[4:]
    with open(items_file) as f:
        campaign = json.load(f)
    item = campaign["items"][name]
    doc = {
        "format": "roverlab-campaign-run",
        "version": 1,
        "name": name,
        "kind": item["kind"],
        "scenario": item["scenario"],
        "source": item["source"],
        "mapping": item["mapping"],
        "seed": item["seed"],
        "effects": item["effects"],
        "roverlab_version": campaign["version"],
        "commands": commands,
        "inputs": [{"file": p, "sha256": sha256(p)} for p in item["inputs"]],
        "report": f"runs/{name}/report/index.html",
    }
    tmp = output + ".tmp"
    with open(tmp, "w") as f:
        json.dump(doc, f, indent=1, sort_keys=True)
        f.write("\n")
    os.replace(tmp, output)


if __name__ == "__main__":
    main()
