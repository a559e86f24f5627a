#!/usr/bin/env python3
"""Local-minimum escape (MODEL §5.2, docs/robotics.md "Escape") on variants
nobody tuned to, with the escape's default settings (issue 37).

A robot (a particle, a round lattice ball, a lattice ball with `round: false`,
a lattice cube; 1 kg each, a little linear damping) starts at the origin with
zero gravity and is attracted (20 N/m, 9 N·s/m, tolerance 2 cm) to a goal
1.1 m along x, behind an obstacle centred at x = 0.6 m: a sphere (r 0.15 m), a
box (0.1 × 0.3 × 0.3 m), a wall (0.05 × 0.4 × 0.4 m) or a U-shaped trap open
towards the robot (a 0.4 × 0.4 m back plate and two 0.3 m sides). Each scene
runs 20 s with `"escape": {}`; the table says whether the goal was reached,
how many virtual obstacles came and what work they injected against the run's
energy scale (summary.json "energy"."scale_J").

usage: escape_variants.py ROBOPHI_BINARY OUT_DIR [NAME,NAME,...]
"""
import json
import os
import subprocess
import sys

ROBOTS = {
    "particle": ({"type": "ball", "radius": 0.05, "mass": 1.0, "linearDamping": 2.0}, "robot:0"),
    "round_ball": ({"type": "ball", "radius": 0.08, "mass": 1.0, "cells": 5,
                    "linearDamping": 0.0247}, "robot:40"),
    "lattice_ball": ({"type": "ball", "radius": 0.08, "mass": 1.0, "cells": 5, "round": False,
                      "linearDamping": 0.0247}, "robot:40"),
    "cube": ({"type": "cube", "size": 0.12, "cells": 3, "mass": 1.0, "linearDamping": 0.074},
             "robot:13"),
}


def box(center, size):
    return {"type": "box", "center": center, "size": size}


OBSTACLES = {
    "sphere": [{"type": "sphere", "center": [0.6, 0, 0], "radius": 0.15}],
    "box": [box([0.6, 0, 0], [0.1, 0.3, 0.3])],
    "wall": [box([0.6, 0, 0], [0.05, 0.4, 0.4])],
    "u_trap": [box([0.75, 0, 0], [0.05, 0.4, 0.4]), box([0.6, 0.2, 0], [0.3, 0.05, 0.4]),
               box([0.6, -0.2, 0], [0.3, 0.05, 0.4])],
}


def scene(robot, obstacle):
    body, centre = ROBOTS[robot]
    return {"robophi": 1, "name": f"escape {robot} {obstacle}", "run": {"duration": 20.0},
            "gravity": [0, 0, 0],
            "objects": [dict(body, name="robot", center=[0, 0, 0])],
            "robotics": {"obstacles": OBSTACLES[obstacle],
                         "goals": [{"name": "goal", "particles": [centre],
                                    "translation": [1.1, 0.0, 0.0], "stiffness": 20,
                                    "damping": 9, "tolerance": 0.02, "stopWhenReached": True,
                                    "escape": {}}]}}


def main():
    binary, out = sys.argv[1], sys.argv[2]
    only = sys.argv[3].split(",") if len(sys.argv) > 3 else None
    os.makedirs(out, exist_ok=True)
    reached = 0
    for robot in ROBOTS:
        for obstacle in OBSTACLES:
            name = f"{robot}_{obstacle}"
            if only and name not in only:
                continue
            path = os.path.join(out, name + ".json")
            with open(path, "w") as f:
                json.dump(scene(robot, obstacle), f, indent=1)
            rc = subprocess.run([binary, "run", path, "--out", os.path.join(out, name), "-q"],
                                capture_output=True, text=True, timeout=600).returncode
            with open(os.path.join(out, name, "summary.json")) as f:
                s = json.load(f)
            goal, energy = s["outcomes"]["goals"][0], s["energy"]
            work = goal.get("escape_work_J", 0.0)
            reached += goal["reached"]
            print(f"{name:20s} exit {rc} reached {str(goal['reached']):5s} "
                  f"{goal['final_distance_m']:.3f} m from the goal, "
                  f"{goal.get('virtual_obstacles', 0):3d} obstacles, work {work:.3g} J "
                  f"({100 * work / energy['scale_J']:.1f} % of {energy['scale_J']:.3g} J), "
                  f"t {s['simulated_time_s']:.2f} s, wall {s['wall_time_s']:.1f} s", flush=True)
    print(f"reached: {reached}")


if __name__ == "__main__":
    main()
