#!/usr/bin/env python3
"""MODEL §5.1-5.2 on a URDF arm, end to end through the command line (issue 37).

For each case: `robophi run` the passive-arm scene (the tool attracted to a
virtual tool that travels through a box grown by a security distance), then
the replay scene with its joints' position servos following the first run's
trajectory.json. Asserts: the goal reached (exit 0), the arm's collision
particles never nearer the real box than `--clearance` (m, their surfaces:
centre distance less radius, at every frame), and the replay's tool within
5 mm and 1° of the passive run's at the end.

usage: urdf_passive_replay.py ROBOPHI_BINARY SOURCE_DIR [--case NAME] [--keep DIR]
Skips (exit 77) when ROBOPHI_ROBOTS_DIR does not name the robots' folder.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import tempfile

# (scene, replay scene, changes to the passive scene): the tuned case, and
# goal/box placements the scene was not tuned to.
CASES = {
    "iiwa": ("iiwa_passive_box.json", "iiwa_replay.json", {}),
    "iiwa_other": ("iiwa_passive_box.json", "iiwa_replay.json",
                   {"box": [0.45, 0.0, 0.21], "size": [0.2, 0.08, 0.42], "target": [0.55, 0.35, 0.55]}),
    "panda": ("panda_passive_box.json", "panda_replay.json", {}),
    # μ 0.1 on the robot (0.22 with the box): stuck against the box's face, a friction
    # local minimum (MODEL §5.2) that virtual obstacles push it out of, with the
    # escape's default settings.
    "iiwa_escape": ("iiwa_passive_box.json", "iiwa_replay.json",
                    {"friction": 0.1, "duration": 12.0, "escape": {}}),
}


def load(path):
    with open(path) as f:
        text = "".join(line for line in f if not line.lstrip().startswith("//"))
    return json.loads(text)


def run(binary, scene, out):
    command = [binary, "run", scene, "--out", out, "--force", "--quiet"]
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"FAIL: {' '.join(command)} exited {done.returncode}\n{done.stderr}")


def last_row(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], [float(x) for x in rows[-1]]


def box_distance(p, center, half):
    d = [max(abs(p[k] - center[k]) - half[k], 0.0) for k in range(3)]
    return math.sqrt(sum(x * x for x in d))


def clearance(run_dir, robot, center, size):
    """Smallest surface distance (m) of the robot's particles to the box over the frames."""
    model = json.load(open(os.path.join(run_dir, "model.json")))
    radius = model["particles"]["radius"]
    mine = [o for o in model["objects"]
            if o["name"].startswith(robot + ".") and o["kind"] != "virtual"]
    indices = [i for o in mine for i in range(o["first"], o["first"] + o["count"])]
    half = [s / 2 for s in size]
    smallest = math.inf
    with open(os.path.join(run_dir, "particles.csv")) as f:
        reader = csv.reader(f)
        next(reader)
        for row in reader:
            for i in indices:
                p = [float(row[1 + 6 * i + k]) for k in range(3)]
                smallest = min(smallest, box_distance(p, center, half) - radius[i])
    return smallest


def tool_path(run_dir):
    """The tool's position (m) at every frame, by time (s)."""
    model = json.load(open(os.path.join(run_dir, "model.json")))
    tool = next(o for o in model["objects"] if o["name"] == "tool")["first"]
    with open(os.path.join(run_dir, "particles.csv")) as f:
        rows = list(csv.reader(f))[1:]
    # Keyed by frame number: frames fall on the first step past each 1/fps.
    return {round(float(r[0]) * 50): [float(x) for x in r[1 + 6 * tool:4 + 6 * tool]] for r in rows}


def tool_pose(run_dir):
    model = json.load(open(os.path.join(run_dir, "model.json")))
    tool = next(o for o in model["objects"] if o["name"] == "tool")["first"]
    _, row = last_row(os.path.join(run_dir, "particles.csv"))
    position = row[1 + 6 * tool:4 + 6 * tool]
    header, sensors = last_row(os.path.join(run_dir, "sensors.csv"))
    q = [sensors[header.index("flange:" + c)] for c in ("qw", "qx", "qy", "qz")]
    return position, q


def check(binary, source, name, keep):
    scene_file, replay_file, change = CASES[name]
    work = keep or tempfile.mkdtemp(prefix="robophi_replay_")
    os.makedirs(work, exist_ok=True)
    scene = load(os.path.join(source, "scenes", scene_file))
    obstacle = scene["robotics"]["obstacles"][0]
    if "box" in change:
        obstacle["center"], obstacle["size"] = change["box"], change["size"]
        scene["robotics"]["goals"][0]["targets"] = [change["target"]]
    if "friction" in change:
        scene["materials"][0]["staticFriction"] = change["friction"]
        scene["materials"][0]["kineticFriction"] = change["friction"]
        scene["robotics"]["goals"][0]["escape"] = change["escape"]
        scene["run"]["duration"] = change["duration"]
    robot = scene["objects"][0]["name"]
    for o in scene["objects"]:  # the robots folder: from the environment, not the scene's
        for key in ("file",):
            o[key] = o[key].replace("$(optenv ROBOPHI_ROBOTS_DIR ../../shared/robots)",
                                    os.environ["ROBOPHI_ROBOTS_DIR"])
        o["packagePaths"] = [p.replace("$(optenv ROBOPHI_ROBOTS_DIR ../../shared/robots)",
                                       os.environ["ROBOPHI_ROBOTS_DIR"]) for p in o["packagePaths"]]
    passive = os.path.join(work, "passive.json")
    json.dump(scene, open(passive, "w"), indent=1)
    run(binary, passive, os.path.join(work, "passive"))
    summary = json.load(open(os.path.join(work, "passive", "summary.json")))
    gap = clearance(os.path.join(work, "passive"), robot, obstacle["center"], obstacle["size"])
    replay = load(os.path.join(source, "scenes", replay_file))
    for o in replay["objects"]:
        o["file"] = scene["objects"][0]["file"]
        o["packagePaths"] = scene["objects"][0]["packagePaths"]
    replay["control"]["replay"]["file"] = os.path.join(work, "passive", "trajectory.json")
    replay["run"]["duration"] = scene["run"]["duration"] + 1.0
    replayed = os.path.join(work, "replay.json")
    json.dump(replay, open(replayed, "w"), indent=1)
    run(binary, replayed, os.path.join(work, "replay"))
    (p1, q1), (p2, q2) = tool_pose(os.path.join(work, "passive")), tool_pose(os.path.join(work, "replay"))
    error = math.dist(p1, p2)
    path1, path2 = tool_path(os.path.join(work, "passive")), tool_path(os.path.join(work, "replay"))
    lag = max(math.dist(path1[t], path2[t]) for t in path1 if t in path2)
    turn = 2 * math.degrees(math.acos(min(1.0, abs(sum(a * b for a, b in zip(q1, q2))))))
    goal = scene["robotics"]["goals"][0]["targets"][0]
    outcome = summary.get("outcomes", {})
    print(f"{name}: goal {goal} reached ({json.dumps(outcome)[:200]}); smallest clearance to the "
          f"box {gap * 1000:.1f} mm; replayed tool {error * 1000:.2f} mm, {turn:.3f} deg from the "
          f"passive run's at the end ({lag * 1000:.1f} mm at most on the way); tool at "
          f"{[round(x, 4) for x in p1]}")
    ok = gap > 0.005 and error < 0.005 and turn < 1.0
    if not ok:
        print(f"FAIL: {name}: clearance {gap:.4f} m (> 0.005), tool error {error:.4f} m (< 0.005), "
              f"turn {turn:.3f} deg (< 1)")
    return ok


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("binary")
    parser.add_argument("source")
    parser.add_argument("--case", action="append", choices=sorted(CASES))
    parser.add_argument("--keep")
    args = parser.parse_args()
    robots = os.environ.get("ROBOPHI_ROBOTS_DIR", "")
    if not os.path.isdir(os.path.join(robots, "kuka_iiwa")):
        print(f"skipped: no robots' folder at ROBOPHI_ROBOTS_DIR='{robots}' (kuka_iiwa, franka_panda)")
        return 77
    results = [check(args.binary, args.source, name,
                     os.path.join(args.keep, name) if args.keep else None)
               for name in (args.case or sorted(CASES))]
    return 0 if all(results) else 1


if __name__ == "__main__":
    sys.exit(main())
