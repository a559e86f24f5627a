"""A grasp experiment swept over a parameter (docs/python.md).

The hand of scenes/hand_grasp.json closes its six flexion joints on the floating
ball (as the scene's grasp task does: each target turns its finger towards the
ball, by 0.8 rad over the first second), here for several servo stiffnesses κ of
the fingers (the scene's is 0.2 N·m/rad). For each κ the script reports, after
4 s, the grip: the number of contacts between hand and ball, the sum of their
normal forces, and how fast the ball still moves.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/grasp_sweep.py
"""

import os
import pathlib

import numpy as np

import robophi

QUICK = os.environ.get("ROBOPHI_EXAMPLE_QUICK") == "1"  # the test runs it short
ROOT = pathlib.Path(__file__).resolve().parents[2]
SECONDS = 0.05 if QUICK else 4.0
STIFFNESSES = [0.2, 0.5] if QUICK else [0.05, 0.1, 0.2, 0.5, 1.0]  # N·m/rad
CLOSE_ANGLE, CLOSE_TIME = 0.8, 1.0  # rad, s


def closing_directions(world, joints, ball):
    """+1 or -1 per joint: the way that turns the finger towards the ball."""
    model = world.model
    p = world.positions
    center = p[ball.particles].mean(axis=0)
    signs = []
    for j in joints:
        js = model.joint_springs[model.joints[j].connector]
        axis = p[js["d"]] - p[js["c"]]
        arm = p[js["b"]] - p[js["c"]]
        signs.append(1.0 if np.dot(np.cross(axis, arm), center - p[js["b"]]) >= 0 else -1.0)
    return np.array(signs)


def grasp(scene, stiffness):
    world = robophi.World(scene)
    model = world.model
    ball = model.object("ball")
    hand = model.object("hand")
    joints = [model.joint(f"hand.f{f}.j{k}") for f in (1, 2, 3) for k in (2, 3)]
    # The scene's servo damping scales as √κ (0.05 √(κ m_min) w², docs/robotics.md).
    springs = model.joint_springs
    for j in range(len(model.joints)):
        kappa0, mu0 = springs["stiffness"][j], springs["damping"][j]
        world.set_joint_servo(j, stiffness, mu0 * np.sqrt(stiffness / kappa0))
    start = world.joint_positions[joints]
    direction = closing_directions(world, joints, ball)

    def close(w):
        closing = min(1.0, w.time / CLOSE_TIME)
        for j, q0, s in zip(joints, start, direction):
            w.set_joint_target(j, q0 + s * closing * CLOSE_ANGLE)

    world.run(SECONDS, callback=close)
    c = world.contacts
    in_ball = (c["a"] >= ball.first_particle) & (c["a"] < ball.first_particle + ball.particle_count)
    other_in_hand = (c["other"] >= hand.first_particle) & \
        (c["other"] < hand.first_particle + hand.particle_count)
    a_in_hand = (c["a"] >= hand.first_particle) & (c["a"] < hand.first_particle + hand.particle_count)
    other_in_ball = (c["other"] >= ball.first_particle) & \
        (c["other"] < ball.first_particle + ball.particle_count)
    grip = (in_ball & other_in_hand) | (a_in_hand & other_in_ball)
    speed = np.linalg.norm(world.velocities[ball.particles].mean(axis=0))
    return grip.sum(), c["normal_force"][grip].sum(), speed


if __name__ == "__main__":
    scene = robophi.load(ROOT / "scenes" / "hand_grasp.json")
    print(f"{'kappa N·m/rad':>14} {'contacts':>9} {'grip N':>9} {'ball speed m/s':>15}")
    for k in STIFFNESSES:
        contacts, force, speed = grasp(scene, k)
        print(f"{k:14.3g} {contacts:9d} {force:9.4f} {speed:15.3e}")
