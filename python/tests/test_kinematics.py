"""The kinematics API and MJCF import from Python (docs/python.md "The robotics toolkit
beside MuJoCo's names"): Jacobians against finite differences of frame_pose, inverse
kinematics within the limits, an MJCF arm as a RigidRobot and as a scene, and an MJCF
element robophi cannot represent refused by name."""

import numpy as np
import pytest

from conftest import SOURCE_DIR

robophi = pytest.importorskip("robophi", reason="the Python module was not built "
                              "(ROBOPHI_BUILD_PYTHON=OFF, or PYTHONPATH lacks build/python)")

ARM = SOURCE_DIR / "tests" / "build" / "mjcf" / "arm.xml"
needs_mujoco = pytest.mark.skipif(not robophi._robophi._mjcf_available(),
                                  reason="robophi was built without libmujoco-dev (MJCF import)")


def test_the_jacobian_of_a_point_is_the_rate_of_its_position(robots):
    robot = robophi.RigidRobot(robots / "kuka_iiwa" / "model.urdf")
    rng = np.random.default_rng(38)
    q = rng.uniform(-1.5, 1.5, 7)
    point = np.array([0.02, -0.01, 0.06])
    J = robot.jacobian("lbr_iiwa_link_7", q, point=point)
    h = 1e-6
    for k in range(7):
        dq = np.zeros(7)
        dq[k] = h
        p_plus = robot.frame_transform("lbr_iiwa_link_7", q + dq) @ np.append(point, 1.0)
        p_minus = robot.frame_transform("lbr_iiwa_link_7", q - dq) @ np.append(point, 1.0)
        assert np.allclose((p_plus - p_minus)[:3] / (2 * h), J[:3, k], atol=1e-7)


def test_inverse_kinematics_keeps_the_limits_and_reports(robots):
    robot = robophi.RigidRobot(robots / "franka_panda" / "panda.urdf",
                               package_paths=[robots / "franka_panda"])
    rng = np.random.default_rng(1)
    q_goal = robot.q
    q_goal[:7] = rng.uniform(robot.lower[:7], robot.upper[:7])
    p, R = robot.frame_pose("panda_link8", q_goal)
    ik = robot.inverse_kinematics("panda_link8", p, R, seed=7)
    assert ik["success"], ik
    assert np.all(ik["q"] >= robot.lower - 1e-12) and np.all(ik["q"] <= robot.upper + 1e-12)
    again = robot.inverse_kinematics("panda_link8", p, R, seed=7)
    assert np.array_equal(again["q"], ik["q"])  # deterministic by seed
    far = robot.inverse_kinematics("panda_link8", position=[5.0, 0, 0], restarts=2)
    assert not far["success"] and far["position_error"] > 3.0


@needs_mujoco
def test_an_mjcf_arm_is_a_rigid_robot_and_a_scene():
    arm = robophi.RigidRobot(ARM)
    assert arm.joint_names == ["j1", "j2", "j3", "j4", "j5", "j6"]
    assert arm.timestep == 0.001
    assert [a["kind"] for a in arm.actuators][-2:] == ["velocity", "motor"]
    assert arm.lower[5] == 0.0 and arm.upper[5] == 0.05
    poses = arm.forward_kinematics(np.zeros(6))
    assert "mjcf_arm.tcp" in poses and "mjcf_arm.flange" in poses
    scene = robophi.load(ARM)
    world = robophi.World(scene)
    world.advance(0.05)


@needs_mujoco
def test_an_mjcf_ball_joint_with_a_cone_limit_is_refused_by_name(tmp_path):
    path = tmp_path / "ball.xml"
    path.write_text('<mujoco model="b">\n<worldbody>\n<body name="arm">\n'
                    '<joint name="shoulder_ball" type="ball" limited="true" range="0 1"/>\n'
                    '<geom type="sphere" size="0.1"/>\n'
                    '</body>\n</worldbody>\n</mujoco>\n')
    with pytest.raises(Exception, match="shoulder_ball"):
        robophi.RigidRobot(path)
    with pytest.raises(robophi.SceneError, match=r"ball.xml:4: error: <joint> 'shoulder_ball'"):
        robophi.load(path)
