"""A control loop in Python holding an arm against gravity (docs/python.md).

A two-link arm, horizontal at the start, hangs on its joint servos (MODEL §1: a
JS with stiffness κ pulls the joint towards its target). Left alone it sags by
about the gravity torque over κ. The PD loop below reads the joint positions and
rates every step and leads the targets by kp times the error, less kd times the
rate: the arm is held 1 + kp = 10 times stiffer, and sags a tenth as much.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/hold_arm.py
"""

import os

import numpy as np

import robophi

QUICK = os.environ.get("ROBOPHI_EXAMPLE_QUICK") == "1"  # the test runs it short
DT = 1e-4  # s
SECONDS = 0.2 if QUICK else 8.0


def make_arm():
    b = robophi.ModelBuilder()
    b.add(robophi.Arm(base=(0.0, 0.0, 1.0), direction=(1.0, 0.0, 0.0), links=[0.5, 0.4],
                      axes=[(0.0, 1.0, 0.0)], mass=1.0, joint_stiffness=20.0, joint_damping=3.0),
          name="arm")
    return b.build()


def hold(use_loop):
    model, state = make_arm()
    world = robophi.World(model, state)
    reference = np.zeros(len(model.joints))  # q = 0: straight and horizontal
    kp, kd = 9.0, 0.1  # -, s

    def controller(w):
        # The targets lead the error: the servo's spring acts as κ (1 + kp), its
        # damping as μ + κ kd (MODEL §1: the JS pulls q towards its target).
        w.set_joint_targets(reference + kp * (reference - w.joint_positions) - kd * w.joint_rates)

    for _ in range(int(round(SECONDS / DT))):
        if use_loop:
            controller(world)
        world.step(DT)
    return world


if __name__ == "__main__":
    alone = hold(False)
    held = hold(True)
    print(f"after {SECONDS} s: servo alone q = {np.round(alone.joint_positions, 4)} rad")
    print(f"                with the PD loop q = {np.round(held.joint_positions, 4)} rad, "
          f"targets {np.round(held.joint_targets, 4)} rad, efforts "
          f"{np.round(held.joint_efforts, 3)} N·m")
    print(f"external work of the target edits: {held.energy.external:.4f} J")
    assert np.max(np.abs(held.joint_positions)) < np.max(np.abs(alone.joint_positions))
