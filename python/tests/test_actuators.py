"""Actuators set between steps from Python (world.set_actuator, set_joint_mode,
set_joint_effort, set_joint_drive; robotics::Controller, MODEL §1.5, §1.6) doing
what they say, against closed forms on a one-link arm turning about a vertical
axis without gravity: a constant effort τ gives q = τ t² / (2 I), a position
servo reaches its target, a rate drive holds its rate."""

import numpy as np
import pytest

robophi = pytest.importorskip("robophi", reason="the Python module was not built "
                              "(ROBOPHI_BUILD_PYTHON=OFF, or PYTHONPATH lacks build/python)")

DT = 1e-4


def turning_arm():
    """A 0.4 m link of 1 kg on a revolute joint about +z, no gravity, no servo: the
    joint's only load is the link's inertia I about the axis."""
    b = robophi.ModelBuilder()
    b.set_gravity((0.0, 0.0, 0.0))
    b.add(robophi.Arm(base=(0.0, 0.0, 1.0), direction=(1.0, 0.0, 0.0), links=[0.4],
                      axes=[(0.0, 0.0, 1.0)], mass=1.0, joint_stiffness=0.0, joint_damping=0.0),
          name="arm")
    model, state = b.build()
    # I = Σ m_i r_i² over the moving particles, r_i their distance from the axis c-d.
    js = model.joint_springs[0]
    c, d = state.positions[js["c"]], state.positions[js["d"]]
    axis = (d - c) / np.linalg.norm(d - c)
    r = state.positions - c
    r_perp = r - np.outer(r @ axis, axis)
    moving = model.inverse_masses > 0
    inertia = float((model.masses[moving] * (r_perp[moving] ** 2).sum(axis=1)).sum())
    return model, state, inertia


def test_effort_mode_gives_the_closed_form_acceleration():
    model, state, inertia = turning_arm()
    world = robophi.World(model, state, integrator="verlet")
    tau, t = 0.05, 0.5  # N·m, s
    world.set_actuator("arm.j1", "effort", target=tau)
    world.run(t, dt=DT)
    # q = ½ (τ / I) t², q̇ = (τ / I) t: within 0.5 % (the link is stiff, not rigid).
    assert world.joint_positions[0] == pytest.approx(0.5 * tau / inertia * t ** 2, rel=5e-3)
    assert world.joint_rates[0] == pytest.approx(tau / inertia * t, rel=5e-3)
    assert world.joint_motor_efforts[0] == tau
    assert world.actuator(0)["mode"] == "effort"


def test_set_joint_effort_is_the_same_motor():
    model, state, inertia = turning_arm()
    world = robophi.World(model, state, integrator="verlet")
    world.set_joint_effort("arm.j1", -0.02)
    world.run(0.5, dt=DT)
    assert world.joint_positions[0] == pytest.approx(-0.5 * 0.02 / inertia * 0.25, rel=5e-3)
    assert world.joint_drive(0).effort == -0.02
    assert world.actuator(0) is None  # a drive edit, no actuator


def test_position_servo_reaches_its_target_then_effort_mode_accelerates():
    model, state, inertia = turning_arm()
    world = robophi.World(model, state, integrator="verlet")
    kp = 2.0  # N·m/rad; critically damped: kd = 2 √(kp I)
    world.set_actuator(0, "position", kp=kp, kd=2 * np.sqrt(kp * inertia), target=0.5)
    world.run(3.0, dt=DT)  # ~15 time constants √(I / kp)
    assert abs(world.joint_positions[0] - 0.5) < 1e-3  # rad
    assert abs(world.joint_rates[0]) < 1e-2  # rad/s
    assert world.actuator(0)["servo_target"] == 0.5
    # Switched between steps: the same actuator in effort mode, τ as its target;
    # from rest at q = 0.5 the closed form again.
    world.set_joint_mode(0, "effort")
    world.set_actuator_target(0, 0.03)
    q0, rate0 = world.joint_positions[0], world.joint_rates[0]
    world.run(0.4, dt=DT)
    expected = q0 + rate0 * 0.4 + 0.5 * 0.03 / inertia * 0.4 ** 2
    assert world.joint_positions[0] == pytest.approx(expected, abs=2e-3)
    # The servo is off in effort mode.
    assert world.joint_efforts[0] == 0.0


def test_velocity_mode_holds_its_rate():
    model, state, inertia = turning_arm()
    world = robophi.World(model, state, integrator="verlet")
    kv = 1.0  # N·m·s/rad: the rate settles with time constant I / kv (~0.08 s)
    world.set_actuator(0, "velocity", kv=kv, target=2.0)
    world.run(1.0, dt=DT)  # ~12 time constants
    assert world.joint_rates[0] == pytest.approx(2.0, abs=2e-3)
    # An effort limit caps the motor: τ = 0.01 N·m from rest (kv q̇* = 2 N·m clamped),
    # q = 0.01 t² / (2 I) while kv (q̇* − q̇) stays above the limit.
    world = robophi.World(model, state, integrator="verlet")
    world.set_actuator(0, "velocity", kv=kv, target=2.0, effort_limit=0.01)
    world.run(0.4, dt=DT)
    assert world.joint_motor_efforts[0] == 0.01
    assert world.joint_positions[0] == pytest.approx(0.5 * 0.01 / inertia * 0.4 ** 2, rel=5e-3)


def test_a_trajectory_target():
    model, state, inertia = turning_arm()
    world = robophi.World(model, state, integrator="verlet")
    ramp = robophi.Trajectory.keyframes([0.0, 1.0], [0.0, 0.3])
    assert ramp.value(0.5) == pytest.approx(0.15) and ramp.rate(0.5) == pytest.approx(0.3)
    world.set_actuator(0, "position", kp=5.0, kd=2 * np.sqrt(5.0 * inertia), target=ramp)
    world.run(2.0, dt=DT)
    assert world.joint_positions[0] == pytest.approx(0.3, abs=1e-3)


def test_rate_drive_through_set_joint_drive():
    model, state, inertia = turning_arm()
    world = robophi.World(model, state, integrator="verlet")
    world.set_joint_drive("arm.j1", rate_gain=1.0, target_rate=-1.0)
    world.run(1.0, dt=DT)
    assert world.joint_rates[0] == pytest.approx(-1.0, abs=2e-3)
    drive = world.joint_drive(0)
    assert (drive.rate_gain, drive.target_rate) == (1.0, -1.0)
    world.set_joint_drive(0, robophi.JointDrive(damping=0.5))  # a whole drive: the motor off
    assert world.joint_drive(0).rate_gain == 0.0 and world.joint_drive(0).damping == 0.5


def test_actuator_errors_name_the_joint_and_field():
    model, state, _ = turning_arm()
    world = robophi.World(model, state)
    with pytest.raises(ValueError, match="set_actuator: joint 'arm.j1': 'kp' = -1 must be"):
        world.set_actuator(0, "position", kp=-1.0)
    with pytest.raises(ValueError, match="mode 'bogus': expected position, velocity, effort"):
        world.set_actuator(0, "bogus")
    with pytest.raises(ValueError, match="set_joint_mode: joint 'arm.j1' has no actuator"):
        world.set_joint_mode(0, "effort")
    with pytest.raises(KeyError, match="no joint named 'elbow'"):
        world.set_actuator("elbow", "effort")
    with pytest.raises(IndexError, match="joint 3 does not exist"):
        world.set_joint_effort(3, 1.0)
    with pytest.raises(ValueError, match="drive rateGain = -1 must be finite and >= 0"):
        world.set_joint_drive(0, rate_gain=-1.0)
    with pytest.raises(TypeError, match="set_joint_drive: no field 'gain'"):
        world.set_joint_drive(0, gain=1.0)
    with pytest.raises(ValueError, match="must be finite"):
        world.set_actuator(0, "effort", target=float("nan"))
    with pytest.raises(ValueError, match="Trajectory.keyframes: keyframe 1"):
        robophi.Trajectory.keyframes([1.0, 0.0], [0.0, 1.0])
