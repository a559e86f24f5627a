"""A control loop in Python: joint targets set between steps hold an arm against gravity."""

import numpy as np
import pytest

robophi = pytest.importorskip("robophi", reason="the Python module was not built "
                              "(ROBOPHI_BUILD_PYTHON=OFF, or PYTHONPATH lacks build/python)")
from util import vertical_arm  # noqa: E402

DT = 1e-4
KAPPA, MU = 20.0, 3.0  # the servos' stiffness (N·m/rad) and damping (N·m·s/rad), util.vertical_arm


def settle(world, seconds, controller=None):
    for _ in range(int(round(seconds / DT))):
        if controller:
            controller(world)
        world.step(DT)


def test_servo_alone_sags_under_gravity():
    model, state = vertical_arm(joint_stiffness=KAPPA)
    world = robophi.World(model, state)
    settle(world, 3.0)
    q, rate = world.joint_positions, world.joint_rates
    # Held by its servos only, the horizontal arm sags by about the gravity torque
    # over the stiffness: ~ m g x_cm / κ ≈ 1.25 kg × 9.81 × 0.4 m / 20 ≈ 0.24 rad.
    assert 0.15 < q[0] < 0.35
    assert np.all(np.abs(rate) < 0.01)
    assert np.all(np.abs(world.joint_targets) < 1e-12)
    # The servo's effort is −κ (q − q_target) − μ q̇.
    assert world.joint_efforts == pytest.approx(-KAPPA * q - MU * rate, rel=1e-12)


def test_a_python_pd_loop_holds_the_arm_ten_times_stiffer():
    model, state = vertical_arm(joint_stiffness=KAPPA)
    alone = robophi.World(model, state)
    settle(alone, 3.0)
    world = robophi.World(model, state)
    reference = np.zeros(2)
    kp, kd = 9.0, 0.1  # -, s

    def controller(w):
        # The targets lead the error: the servo's spring acts as κ (1 + kp), its
        # damping as μ + κ kd.
        w.set_joint_targets(reference + kp * (reference - w.joint_positions) - kd * w.joint_rates)

    settle(world, 8.0, controller)
    # The sag falls by 1 + kp = 10 (within the slow swing left after 8 s).
    ratio = world.joint_positions / alone.joint_positions
    assert np.all((0.07 < ratio) & (ratio < 0.13)), ratio
    assert abs(world.joint_targets[0]) > 0.15  # the targets lead, where the arm stays near 0
    # Target edits do work on the arm from outside: booked.
    assert world.energy.external != 0.0
