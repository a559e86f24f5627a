"""Actuator modes switched between steps (docs/python.md "Actuators").

A two-link arm in gravity (joint axes +y: gravity loads both joints) is driven
through three phases, each set from Python between steps:

1. position: servos (kp, kd) bring both joints towards q* = (0.4, -0.6) rad; the
   shoulder sags below its target by about its gravity torque over kp;
2. effort: the shoulder's actuator is switched to a constant torque equal and
   opposite to gravity's at that pose (computed from the particles), its servo
   off: the arm stays nearly where it was, where the same arm left passive falls;
3. velocity: the shoulder turns under a rate drive kv (q̇* − q̇), q̇* = 1 rad/s; on
   the way down gravity's torque makes it faster by about τ_g / kv.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/joint_modes.py
"""

import os

import numpy as np

import robophi

QUICK = os.environ.get("ROBOPHI_EXAMPLE_QUICK") == "1"  # the test runs it short
DT = 1e-4  # s
PHASE = 0.1 if QUICK else 1.5  # s a phase


def make_arm():
    b = robophi.ModelBuilder()
    b.add(robophi.Arm(base=(0.0, 0.0, 1.0), direction=(1.0, 0.0, 0.0), links=[0.5, 0.4],
                      axes=[(0.0, 1.0, 0.0)], mass=1.0, joint_stiffness=0.0, joint_damping=0.0),
          name="arm")
    return b.build()


def gravity_torque(world, model):
    """The torque (N·m) gravity puts on the shoulder, about its axis (+y): Σ (r × m g)·y
    over the moving particles, r from the shoulder's axis."""
    js = model.joint_springs[model.joints[0].connector]
    p = world.positions
    axis = p[js["d"]] - p[js["c"]]
    axis /= np.linalg.norm(axis)
    moving = model.inverse_masses > 0
    r = p[moving] - p[js["c"]]
    weight = model.masses[moving, None] * np.asarray(model.gravity)
    return float(np.cross(r, weight).sum(axis=0) @ axis)


def report(name, world):
    q, rate = world.joint_positions, world.joint_rates
    print(f"{name:>9}  t = {world.time:5.2f} s  q = ({q[0]:+.3f}, {q[1]:+.3f}) rad  "
          f"q̇ = ({rate[0]:+.3f}, {rate[1]:+.3f}) rad/s  "
          f"motor = {world.joint_motor_efforts[0]:+.3f} N·m")


def main():
    model, state = make_arm()
    world = robophi.World(model, state, integrator="verlet")
    for joint, target in (("arm.j1", 0.4), ("arm.j2", -0.6)):
        world.set_actuator(joint, "position", kp=20.0, kd=3.0, target=target)
    world.run(PHASE, dt=DT)
    report("position", world)
    sag = gravity_torque(world, model) / 20.0
    print(f"           the shoulder's gravity torque / kp = {sag:+.3f} rad of sag")

    # The shoulder's torque that balances gravity at this pose, as a plain effort
    # (the actuator's target is τ in effort mode), against the shoulder left passive.
    hold = -gravity_torque(world, model)
    before = world.snapshot()
    q_before = world.joint_positions[0]
    world.set_joint_mode("arm.j1", "passive")
    world.run(PHASE / 3, dt=DT)
    fell = world.joint_positions[0] - q_before
    world.restore(before)
    world.set_joint_mode("arm.j1", "effort")
    world.set_actuator_target("arm.j1", hold)
    world.run(PHASE / 3, dt=DT)
    report("effort", world)
    print(f"           {hold:+.3f} N·m held the shoulder: it moved "
          f"{world.joint_positions[0] - q_before:+.4f} rad in {PHASE / 3:.2f} s "
          f"(passive: {fell:+.4f} rad)")

    world.set_actuator("arm.j1", "velocity", kv=10.0, target=1.0)
    world.run(PHASE / 3, dt=DT)
    report("velocity", world)


if __name__ == "__main__":
    main()
