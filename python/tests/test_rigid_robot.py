"""Rigid robots from Python (robophi.RigidRobot, docs/python.md "Rigid robots"): a
URDF as rigid bodies with exact mass properties; a joint PD written in Python holds
the iiwa at MuJoCo's gains at 1 kHz with gravity compensation from the library."""

import numpy as np
import pytest

robophi = pytest.importorskip("robophi", reason="the Python module was not built "
                              "(ROBOPHI_BUILD_PYTHON=OFF, or PYTHONPATH lacks build/python)")


def test_iiwa_held_by_a_python_pd_with_gravity_compensation(robots):
    robot = robophi.RigidRobot(robots / "kuka_iiwa" / "model.urdf")
    assert robot.nv == 7 and len(robot.joint_names) == 7
    target = np.array([0, 1.0, 0, -1.0, 0, 0, 0])
    robot.q = np.zeros(7)  # start away from the pose: the PD must bring it there
    kp, kd = np.full(7, 300.0), np.full(7, 20.0)
    for _ in range(10000):  # 10 s at 1 kHz, efforts set every millisecond
        tau = robot.gravity_forces()
        robot.step(1e-3, effort=tau, kp=kp, kd=kd, target=target)
    assert np.max(np.abs(robot.q - target)) < 1e-4


def test_dynamics_terms_are_consistent(robots):
    robot = robophi.RigidRobot(robots / "franka_panda" / "panda.urdf",
                               package_paths=[robots / "franka_panda"])
    rng = np.random.default_rng(3)
    q = rng.uniform(-1, 1, robot.nq)
    v = rng.uniform(-1, 1, robot.nv)
    M = robot.mass_matrix(q)
    assert np.allclose(M, M.T) and np.all(np.linalg.eigvalsh(M) > 0)
    robot.q, robot.v = q, v
    kinetic, _ = robot.energy()
    assert kinetic == pytest.approx(0.5 * v @ M @ v, rel=1e-12)
    # The bias at v = 0 is gravity alone.
    assert np.allclose(robot.bias_forces(q, np.zeros(robot.nv)), robot.gravity_forces(q))


def test_frame_pose_and_jacobian_agree(robots):
    robot = robophi.RigidRobot(robots / "kuka_iiwa" / "model.urdf")
    q = np.array([0.3, 0.8, -0.2, -1.1, 0.4, 0.6, -0.3])
    J = robot.jacobian("lbr_iiwa_link_7", q)
    p0, _ = robot.frame_pose("lbr_iiwa_link_7", q)
    dq = 1e-7 * np.array([1, -2, 3, 1, -1, 2, 1])
    p1, _ = robot.frame_pose("lbr_iiwa_link_7", q + dq)
    assert np.allclose(np.array(p1) - np.array(p0), J[:3] @ dq, atol=1e-12)
    with pytest.raises(KeyError, match="no frame named 'nope'"):
        robot.frame_pose("nope")


def test_limits_are_hard_stops(robots):
    robot = robophi.RigidRobot(robots / "kuka_iiwa" / "model.urdf")
    for _ in range(2000):
        robot.step(1e-3, effort=np.full(7, 150.0))
    assert np.all(robot.q <= robot.upper + 1e-3)


def test_a_line_task_tracked_by_joint_pd_through_inverse_kinematics(robots):
    """Issue 35's line task: the iiwa's flange along a 0.2 m line (minimum-jerk over 2 s,
    then 0.5 s held) by a joint PD in Python (kp 300, kd 20, 1 kHz, gravity compensation
    from the library), its joint targets from the library's inverse kinematics at each
    millisecond: the flange stays within 2 mm RMS of the line's point at that time."""
    robot = robophi.RigidRobot(robots / "kuka_iiwa" / "model.urdf")
    frame = "lbr_iiwa_link_7"
    q0 = np.array([0.0, 0.6, 0.0, -1.2, 0.0, 0.9, 0.0])
    robot.q = q0.copy()
    p0, R0 = robot.frame_pose(frame, q0)
    kp, kd = np.full(7, 300.0), np.full(7, 20.0)
    dt, T, hold = 1e-3, 2.0, 0.5
    target, previous = q0.copy(), q0.copy()
    errors = []
    for k in range(int(round((T + hold) / dt))):
        t = (k + 1) * dt
        s = min(t / T, 1.0)
        point = p0 + np.array([0.0, 0.2 * (10 * s**3 - 15 * s**4 + 6 * s**5), 0.0])
        ik = robot.inverse_kinematics(frame, point, R0, q0=target, restarts=0)
        assert ik["success"], f"t = {t:.3f} s: {ik}"
        previous, target = target, ik["q"]
        robot.step(dt, effort=robot.gravity_forces(), kp=kp, kd=kd, target=target,
                   target_rate=(target - previous) / dt)
        p, _ = robot.frame_pose(frame)
        errors.append(np.linalg.norm(p - point))
    rms = float(np.sqrt(np.mean(np.square(errors))))
    print(f"line task: RMS {rms * 1e3:.3f} mm, worst {max(errors) * 1e3:.3f} mm, at the end "
          f"{errors[-1] * 1e3:.4f} mm over {T + hold} s")
    assert rms < 2e-3
    assert errors[-1] < 2e-4, errors[-1]  # settled on the line's end after the hold
