#!/usr/bin/env python3
"""The pick's outcome from a results folder, as ../shared/peers/mujoco/mj_pick.c prints
MuJoCo's (docs/performance.md "Rigid bodies against MuJoCo"): the box's rise, the range
of its height over the hold and its slip relative to the left finger over the hold.

usage: pick_outcome.py RESULTS_DIR [BOX [FINGER]]
"""
import csv
import json
import sys


def main():
    folder = sys.argv[1]
    box = sys.argv[2] if len(sys.argv) > 2 else "box"
    finger = sys.argv[3] if len(sys.argv) > 3 else "panda.panda_leftfinger"
    summary = json.load(open(f"{folder}/summary.json"))
    model = json.load(open(f"{folder}/model.json"))
    names = [o["name"] for o in model["objects"]]
    ib, jf = names.index(box), names.index(finger)
    phases = {p["name"]: p.get("started_s") for p in summary["outcomes"]["control"]["phases"]}
    rows = {}
    with open(f"{folder}/objects.csv") as f:
        for r in csv.DictReader(f):
            o = int(r["object"])
            if o in (ib, jf):
                rows.setdefault(float(r["t"]), {})[o] = (float(r["x"]), float(r["y"]), float(r["z"]))
    times = sorted(t for t in rows if len(rows[t]) == 2)
    hold = phases.get("hold")
    z0 = rows[times[0]][ib][2]
    after = [t for t in times if hold is not None and t >= hold]
    rel = lambda t: [rows[t][ib][k] - rows[t][jf][k] for k in range(3)]
    zs = [rows[t][ib][2] for t in after]
    slip = sum((a - b) ** 2 for a, b in zip(rel(after[-1]), rel(after[0]))) ** 0.5 if after else float("nan")
    print(f"RESULT robophi_pick steps={summary['steps']} wall_s={summary['wall_time_s']:.4f} "
          f"t_close={phases.get('close')} t_lift={phases.get('lift')} t_hold={hold} "
          f"box_rise_m={rows[times[-1]][ib][2] - z0:.5f} "
          f"hold_z_range_m={(max(zs) - min(zs)) if zs else float('nan'):.2e} slip_over_hold_m={slip:.2e} "
          f"status={summary['status']}")


if __name__ == "__main__":
    main()
