#!/usr/bin/python3
"""The placement matrix of issue 36 from the command line: a 3x3x2 box (0.15 x 0.15
x 0.1 m, 1 kg), as a lattice and faceted, mu_s 0.5, mu_k 0.3, set on slopes of 10,
20, 24 and 26 degrees (gravity tilted about y) in five ways (zero gap, dropped
from 1 mm, embedded 1e-5 m, kappa_c 1e5 and 1e7), run at a constant step for 2 s
(1 s at kappa_c 1e7); prints each case's creep along the slope from the start
(the fall of a dropped box included) and from 0.5 s to the end with the end
speed, and how many hold (creep under 1 mm) and how many are at rest after
landing (under 0.1 mm from 0.5 s on, end speed under 1e-4 m/s). The same scenes as tests/collision/test_slope_placement.cpp.

  bench/slope_placement.py ROBOPHI [--damping 30] [--contact '{"tangentialStiffnessRatio": 1}']
                           [--body '{"damping": 20}'] [--only l26] [--out /tmp/slope]

--damping is the pair's mu_c at kappa_c 5e4 (N s/m; scaled with sqrt(kappa_c)),
30 (zeta about 0.2 for a bottom contact's share of the box) by default; --contact
adds a scene 'contact' section; --body adds keys to the box's object (its
connectors' damping, "rigid": true). Standard library only.
"""

import argparse
import concurrent.futures
import csv
import json
import math
import os
import subprocess

PLACEMENTS = {  # gap (m; < 0 embedded), kappa_c (N/m), step (s), seconds
    "zeroGap": (0.0, 5e4, 1e-4, 2.0),
    "dropped1mm": (1e-3, 5e4, 1e-4, 2.0),
    "embedded": (-1e-5, 5e4, 1e-4, 2.0),
    "kappa1e5": (0.0, 1e5, 1e-4, 2.0),
    "kappa1e7": (0.0, 1e7, 1e-5, 1.0),
}


def scene(degrees, placement, facets, damping, contact, body=None):
    gap, kappa, _, _ = PLACEMENTS[placement]
    a = math.radians(degrees)
    pair_damping = damping * math.sqrt(kappa / 5e4)
    s = {"robophi": 1, "name": "slope", "gravity": [9.81 * math.sin(a), 0, -9.81 * math.cos(a)],
         # A material is half of a contact (springs in series): twice the pair's.
         "materials": [{"name": "m", "contactStiffness": 2 * kappa, "contactDamping": 2 * pair_damping,
                        "staticFriction": 0.5, "kineticFriction": 0.3}],
         "environment": {"ground": {"material": "m"}},
         "objects": [{"name": "box", "type": "box", "center": [0, 0, 0.05 + gap], "size": [0.15, 0.15, 0.1],
                      "cells": [3, 3, 2], "mass": 1, "material": "m", "facets": facets}]}
    if contact:
        s["contact"] = contact
    s["objects"][0].update(body or {})
    return s


def run_case(args, case):
    degrees, placement, facets = case
    _, _, step, seconds = PLACEMENTS[placement]
    name = f"{'faceted' if facets else 'lattice'}_{degrees}deg_{placement}"
    folder = os.path.join(args.out, name)
    with open(folder + ".json", "w") as f:
        json.dump(scene(degrees, placement, facets, args.damping, args.contact, args.body), f)
    r = subprocess.run([args.robophi, "run", folder + ".json", "--out", folder, "--force", "--quiet",
                        "--step", "constant", "--dt", str(step), "--duration", str(seconds), "--fps", "10"],
                       capture_output=True, text=True)
    rows = [row for row in csv.DictReader(open(os.path.join(folder, "objects.csv"))) if row["object"] == "0"]
    landed = next(row for row in rows if float(row["t"]) >= 0.5 - 1e-9)
    speed = math.sqrt(sum(float(rows[-1][k]) ** 2 for k in ("vx", "vy", "vz")))
    return (name, r.returncode, float(rows[-1]["x"]) - float(rows[0]["x"]),
            float(rows[-1]["x"]) - float(landed["x"]), speed)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("robophi")
    parser.add_argument("--damping", type=float, default=30.0)
    parser.add_argument("--contact", type=json.loads, default={})
    parser.add_argument("--body", type=json.loads, default={})
    parser.add_argument("--only", default="")
    parser.add_argument("--out", default="/tmp/robophi-slope-placement")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    cases = [(d, p, f) for f in (False, True) for d in (10, 20, 24, 26) for p in PLACEMENTS]
    cases = [c for c in cases if args.only in f"{'faceted' if c[2] else 'lattice'}_{c[0]}deg_{c[1]}"]
    with concurrent.futures.ThreadPoolExecutor(2) as pool:
        results = list(pool.map(lambda c: run_case(args, c), cases))
    held = rested = 0
    for name, code, creep, after, speed in results:
        holds = abs(creep) < 1e-3
        rests = abs(after) < 1e-4 and speed < 1e-4
        held += holds
        rested += rests
        print(f"{name:32s} exit {code} creep {creep:+.3e} m {'holds ' if holds else 'slides'}"
              f"  after 0.5 s {after:+.3e} m, end speed {speed:.1e} m/s {'at rest' if rests else 'moving'}")
    print(f"{held} of {len(results)} hold (creep under 1 mm from the start)")
    print(f"{rested} of {len(results)} at rest after landing (under 0.1 mm from 0.5 s to the end, "
          f"end speed under 1e-4 m/s)")


if __name__ == "__main__":
    main()
