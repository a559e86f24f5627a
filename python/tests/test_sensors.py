"""Sensors and vector I/O on robophi.World (docs/python.md "Sensors and vector I/O"):
a contact sensor under a resting box reads m g at its centre, an IMU reads 0 in free
fall, sensors leave the state hash unchanged, joints read and write as arrays, and
gravity compensation switches at run time; a Python loop holds the iiwa with
tau = bias(q, q̇) + PD within 1e-4 rad."""

import json

import numpy as np
import pytest

robophi = pytest.importorskip("robophi", reason="the Python module was not built "
                              "(ROBOPHI_BUILD_PYTHON=OFF, or PYTHONPATH lacks build/python)")

G = 9.81


def _scene(tmp_path, objects, sensors=(), **extra):
    path = tmp_path / "scene.json"
    path.write_text(json.dumps({"objects": list(objects), "environment": {"ground": True},
                                "sensors": list(sensors), **extra}))
    return robophi.load(path)


def _box(name="box", center=(0, 0, 0.052), side=0.1, mass=0.5, **more):
    return {"name": name, "type": "box", "center": list(center), "size": [side] * 3,
            "cells": [3, 3, 3], "mass": mass, "rigid": True, **more}


def _iiwa(robots, **more):
    file = robots / "kuka_iiwa" / "model.urdf"
    if not file.exists():
        pytest.skip(f"no {file} (set ROBOPHI_ROBOTS_DIR)")
    return {"name": "arm", "type": "urdf", "file": str(file), "rigid": True, "holdJoints": True,
            "initialPositions": {"lbr_iiwa_joint_2": 0.6, "lbr_iiwa_joint_4": -1.1}, **more}


@pytest.mark.parametrize("mass, side", [(0.5, 0.1), (2.3, 0.14)])
def test_contact_sensor_of_a_resting_box(tmp_path, mass, side):
    world = robophi.World(_scene(tmp_path, [_box(center=(0.2, -0.1, side / 2 + 0.002), side=side,
                                                 mass=mass)]))
    world.add_sensor("floor", "contact", "box")
    world.run(1.0, dt=2e-4)
    fx, fy, fz, px, py, pz, fn = world.sensor("floor")
    assert fz == pytest.approx(mass * G, rel=0.005) and fn == pytest.approx(mass * G, rel=0.005)
    assert abs(px) < 1e-3 and abs(py) < 1e-3  # the centre's projection, in the box's frame


def test_imu_in_free_fall_and_the_columns(tmp_path):
    world = robophi.World(_scene(tmp_path, [_box(center=(0, 0, 30), velocity=[1, 0, 2])]))
    world.add_sensor("imu", "imu", "box", position=[0.03, 0, 0])
    world.run(0.5, dt=1e-3)
    assert np.all(np.abs(world.sensor("imu")[:3]) < 1e-6)
    assert world.sensor_names == ["imu"]
    assert world.sensor_columns[:3] == ["imu:ax", "imu:ay", "imu:az"]
    assert world.sensordata.shape == (10,)
    with pytest.raises(KeyError):
        world.sensor("nothing")
    with pytest.raises(ValueError, match="no link or object named 'nothing'"):
        world.add_sensor("x", "imu", "nothing")
    with pytest.raises(ValueError, match="unknown type"):
        world.add_sensor("x", "gyro", "box")


def test_sensors_leave_the_state_hash_unchanged(tmp_path, robots):
    sensors = [{"name": "ft", "type": "force_torque", "on": "arm.lbr_iiwa_joint_2"},
               {"name": "touch", "type": "contact", "on": "box"}]
    sensed = robophi.World(_scene(tmp_path, [_iiwa(robots), _box(center=(0.5, 0.5, 0.052))],
                                  sensors))
    sensed.add_sensor("imu", "imu", "lbr_iiwa_link_7")
    plain = robophi.World(_scene(tmp_path, [_iiwa(robots), _box(center=(0.5, 0.5, 0.052))]))
    readings = []
    sensed.run(0.2, dt=1e-3, callback=lambda w: readings.append(w.sensordata))  # every step
    plain.run(0.2, dt=1e-3)
    assert len(readings) == 200 and sensed.hash() == plain.hash()


def test_joints_as_arrays(tmp_path, robots):
    world = robophi.World(_scene(tmp_path, [_iiwa(robots)]))
    robot = robophi.RigidRobot(robots / "kuka_iiwa" / "model.urdf")
    assert world.joint_names == ["arm." + n for n in robot.joint_names]
    limits = world.joint_limits
    assert np.allclose(limits["lower"], robot.lower) and np.allclose(limits["upper"], robot.upper)
    assert np.allclose(limits["effort"], robot.effort_limit)
    with pytest.raises(ValueError, match="expected 7 efforts"):
        world.set_joint_efforts(np.zeros(3))
    world.set_joint_gains(kp=np.full(7, 123.0), kd=np.r_[np.full(6, np.nan), 7.0])
    drive = world.joint_drive(0)
    assert drive is not None
    with pytest.raises(ValueError, match="robot 'nobody'"):
        world.set_gravity_compensation("nobody", True)
    assert world.set_gravity_compensation("arm", False) == 7


def test_python_pd_with_bias_forces_holds_the_iiwa(tmp_path, robots):
    """tau = bias(q, q̇) + PD, set each millisecond as one array, holds within 1e-4 rad."""
    world = robophi.World(_scene(tmp_path, [_iiwa(robots)]))
    robot = robophi.RigidRobot(robots / "kuka_iiwa" / "model.urdf")
    target = world.joint_positions.copy()
    world.set_gravity_compensation("arm", False)
    world.set_joint_gains(kp=0.0, kd=0.0)
    errors = []
    for _ in range(3000):
        q, qd = world.joint_positions, world.joint_rates
        world.set_joint_efforts(robot.bias_forces(q, qd) - 60.0 * (q - target) - 2.0 * qd)
        world.step(1e-3)
        errors.append(np.max(np.abs(world.joint_positions - target)))
    print(f"held by a Python PD + bias: largest error {max(errors):.2e} rad, last {errors[-1]:.2e} rad")
    assert max(errors) < 1e-4


def test_gravity_compensation_at_run_time(tmp_path, robots):
    world = robophi.World(_scene(tmp_path, [_iiwa(robots)]))
    target = world.joint_positions.copy()
    world.set_gravity_compensation("arm", False)
    world.run(0.5, dt=1e-3)
    sag = np.max(np.abs(world.joint_positions - target))
    world.set_gravity_compensation(None, True)
    world.run(1.0, dt=1e-3)
    back = np.max(np.abs(world.joint_positions - target))
    print(f"compensation off: sags {sag:.3e} rad; on again: {back:.2e} rad")
    assert sag > 1e-3 and back < 1e-4


def test_python_computed_torque_moves_and_holds_the_iiwa(tmp_path, robots):
    """A 0.01 rad step of every joint's target, taken by tau = bias(q, q̇) + M(q) (−kp e − kd ė)
    + b q̇ (the URDF's joint damping b = 0.5 N·m·s/rad, which bias_forces leaves out), set as
    one array each millisecond: within 1e-4 rad from 0.5 s on."""
    world = robophi.World(_scene(tmp_path, [_iiwa(robots)]))
    robot = robophi.RigidRobot(robots / "kuka_iiwa" / "model.urdf")
    target = world.joint_positions + 0.01
    world.set_gravity_compensation("arm", False)
    world.set_joint_gains(kp=0.0, kd=0.0)
    errors = []
    for _ in range(2000):
        q, qd = world.joint_positions, world.joint_rates
        tau = robot.bias_forces(q, qd) + 0.5 * qd + robot.mass_matrix(q) @ (-400.0 * (q - target)
                                                                             - 40.0 * qd)
        world.set_joint_efforts(tau)
        world.step(1e-3)
        errors.append(np.max(np.abs(world.joint_positions - target)))
    print(f"computed torque: error {errors[499]:.2e} rad at 0.5 s, at most {max(errors[500:]):.2e} "
          f"rad after, {errors[-1]:.2e} rad at 2 s")
    assert max(errors[500:]) < 1e-4


def test_contact_and_imu_on_a_particle_box_at_rest(tmp_path):
    """A box of particles tied by springs (not rigid): its contact sensor reads m g at its
    centre's projection, its IMU (its particles' mean motion, fitted frame) g upwards."""
    box = {"name": "box", "type": "box", "center": [0.1, 0.2, 0.06], "size": [0.1, 0.1, 0.1],
           "cells": [3, 3, 3], "mass": 0.5}
    world = robophi.World(_scene(tmp_path, [box]))
    world.add_sensor("floor", "contact", "box")
    world.add_sensor("imu", "imu", "box")
    world.run(2.0, dt=1e-4)
    fx, fy, fz, px, py, pz, fn = world.sensor("floor")
    ax, ay, az = world.sensor("imu")[:3]
    print(f"particle box at rest: fz {fz:.6f} N (m g {0.5 * G:.6f}), centre of pressure "
          f"({px:.1e}, {py:.1e}) m, IMU {az:.6f} m/s²")
    assert fz == pytest.approx(0.5 * G, rel=0.005) and abs(px) < 1e-3 and abs(py) < 1e-3
    assert az == pytest.approx(G, rel=0.005) and abs(ax) < 0.01 and abs(ay) < 0.01


@pytest.mark.parametrize("link", ["lbr_iiwa_link_4", "lbr_iiwa_link_7"])
def test_link_poses_of_a_running_world_equal_forward_kinematics(tmp_path, robots, link):
    """world.link_pose (data.xpos, data.xmat) while the arm moves equals RigidRobot's forward
    kinematics at the world's joint reading, relative to the base (the world sets the robot
    down on the ground), within 0.1 mm and 1e-6 rad."""
    world = robophi.World(_scene(tmp_path, [_iiwa(robots)]))
    robot = robophi.RigidRobot(robots / "kuka_iiwa" / "model.urdf")
    start = world.joint_positions.copy()
    world.set_joint_targets(start + np.array([0.4, -0.3, 0.5, 0.3, -0.6, 0.5, 1.0]))
    worst_p, worst_r = 0.0, 0.0
    for _ in range(6):
        world.run(0.1, dt=1e-3)
        q = world.joint_positions
        p0, R0, p, R, f0, F0, f, F = map(np.asarray, (*world.link_pose("lbr_iiwa_link_0"),
                                                       *world.link_pose(link),
                                                       *robot.frame_pose("lbr_iiwa_link_0", q),
                                                       *robot.frame_pose(link, q)))
        worst_p = max(worst_p, np.linalg.norm(R0.T @ (p - p0) - F0.T @ (f - f0)))
        turn = (R0.T @ R).T @ (F0.T @ F)
        worst_r = max(worst_r, np.arccos(np.clip((np.trace(turn) - 1) / 2, -1, 1)))
    print(f"{link}: link pose against FK at the joint reading: {worst_p:.1e} m, {worst_r:.1e} rad")
    assert np.max(np.abs(world.joint_positions - start)) > 0.1  # the arm moved
    assert worst_p < 1e-4 and worst_r < 1e-6
    with pytest.raises(KeyError, match="no rigid robot's link"):
        world.link_pose("nope")
