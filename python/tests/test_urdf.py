"""URDF robots from Python: robophi.load of a bare URDF is the scene `robophi run
ROBOT.urdf` runs (same model, same state hash), robophi.Urdf placed by a
ModelBuilder, and the importer's errors with the URDF's file:line. Whole URDF
robots do not run long yet (docs/robots.md "Status"): a few steps only."""

import json
import subprocess

import numpy as np
import pytest

robophi = pytest.importorskip("robophi", reason="the Python module was not built "
                              "(ROBOPHI_BUILD_PYTHON=OFF, or PYTHONPATH lacks build/python)")


def test_load_a_bare_urdf(robots):
    # The paper's particle robot (rigid=False, --particles): one object a link.
    scene = robophi.load(robots / "cartpole" / "cartpole.urdf", rigid=False)
    model = scene.model
    assert [j.name for j in model.joints] == ["physics.slider_to_cart", "physics.cart_to_pole"]
    assert [j.kind for j in model.joints] == ["prismatic", "revolute"]
    assert scene.duration == 2.0  # a bare URDF's run (loadUrdfFile)
    robot, = scene.urdf_robots
    assert robot["name"] == "physics"
    joints = {j["name"]: j for j in robot["joints"]}
    assert joints["slider_to_cart"]["type"] == "prismatic"
    assert (joints["slider_to_cart"]["lower"], joints["slider_to_cart"]["upper"]) == (-15, 15)
    assert joints["slider_to_cart"]["velocity"] == 5 and joints["slider_to_cart"]["effort"] == 1000
    pole = joints["cart_to_pole"]
    assert pole["type"] == "continuous" and pole["lower"] is None
    assert joints["cart_to_pole"]["model_joint"] == "physics.cart_to_pole"
    links = {link["name"]: link for link in robot["links"]}
    assert links["pole"]["declared"]["mass"] == 10
    assert links["pole"]["achieved"]["mass"] == pytest.approx(10, rel=1e-9)
    # The ignored elements are the CLI's warnings, FILE:LINE: warning: ...
    assert any(w.endswith("cartpole.urdf:5: warning: <visual> ignored (robophi does not model "
                          "it; one warning for all of them)") for w in scene.warnings)
    # On the ground plane z = 0: the lowest link particle's bottom at z = 0.
    link_particles = np.concatenate([np.arange(model.particle_count)[o.particles]
                                     for o in model.objects if o.kind == "link"])
    bottoms = scene.initial.positions[link_particles, 2] - model.radii[link_particles]
    assert bottoms.min() == pytest.approx(0.0, abs=1e-12)


def test_a_bare_urdf_is_the_clis_scene(robots, tmp_path, cli):
    """robophi.run of the loaded URDF ends on the CLI run's state hash (a few steps)."""
    urdf = robots / "pr2_gripper" / "pr2_gripper.urdf"
    scene = robophi.load(urdf)
    result = robophi.run(scene, out=str(tmp_path / "py"), duration=0.002, step="constant",
                         dt=1e-4, replay=False)
    assert result["status"] == "ok", result["failure"]
    assert result["steps"] == 20
    done = subprocess.run([cli, "run", str(urdf), "--out", str(tmp_path / "cli"), "--duration",
                           "0.002", "--step", "constant", "--dt", "1e-4", "--quiet"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    summary = json.loads((tmp_path / "cli" / "summary.json").read_text())
    assert summary["state_hash"] == result["state_hash"]
    # robophi.run of the path (the CLI's defaults), and a Python loop of the same steps.
    by_path = robophi.run(urdf, out=str(tmp_path / "path"), duration=0.002, step="constant",
                          dt=1e-4, replay=False)
    assert by_path["state_hash"] == result["state_hash"]
    world = robophi.World(scene)
    world.run(0.002, dt=1e-4)
    assert robophi.format_hash(world.hash()) == result["state_hash"]


def test_urdf_options(robots):
    urdf = robots / "pr2_gripper" / "pr2_gripper.urdf"
    fixed = robophi.load(urdf, base="fixed", rigid=False)
    free = robophi.load(urdf, base="free", rigid=False)
    assert (fixed.model.inverse_masses == 0).any()
    assert not (free.model.inverse_masses == 0).any()
    coarse = robophi.load(urdf, particles_per_link=10, rigid=False)
    assert coarse.model.particle_count < fixed.model.particle_count
    with pytest.raises(ValueError, match="robophi.load: base 'sideways': expected fixed or free"):
        robophi.load(urdf, base="sideways")
    with pytest.raises(TypeError, match="are for a URDF"):
        robophi.load(robots / ".." / "nothing.json", base="fixed")
    with pytest.raises(TypeError, match="are for a URDF"):
        robophi.load(robots / ".." / "nothing.json", rigid=False)
    # Rigid, the default: the links are rigid bodies of one tree, exact mass.
    rigid = robophi.load(urdf)
    assert rigid.model.particle_count > 0 and [j.name for j in rigid.model.joints] == \
        [j.name for j in fixed.model.joints]


def test_a_few_steps_of_a_loaded_urdf(robots):
    scene = robophi.load(robots / "pr2_gripper" / "pr2_gripper.urdf")
    world = robophi.World(scene)
    q0 = world.joint_positions.copy()
    for _ in range(50):
        world.step(1e-4)
    assert np.isfinite(world.positions).all()
    # Held by their servos: the joints stay where they were built.
    assert np.abs(world.joint_positions - q0).max() < 1e-3


def test_urdf_builder_spec(robots):
    def build(position):
        b = robophi.ModelBuilder()
        b.add_plane()
        spec = robophi.Urdf(file=robots / "pr2_gripper" / "pr2_gripper.urdf", name="grip",
                            position=position, particles_per_link=12)
        assert spec.fixed_base and not spec.hold_joints and spec.round_wheels  # UrdfSpec's
        placed = b.add_urdf(spec)
        return placed, b.build()

    placed, (model, state) = build((0.0, 0.0, 0.5))
    assert placed["name"] == "physics"
    names = [o[0] for o in placed["objects"]]
    assert "grip.gripper_pole" in names and "grip.left_tip.carriers" in names
    assert [j.name for j in model.joints] == ["grip.left_gripper_joint", "grip.right_gripper_joint"]
    assert placed["model_joints"] == [0, 1, -1, -1]
    assert [j["type"] for j in placed["joints"]] == ["revolute", "revolute", "fixed", "fixed"]
    # The root link's frame at (0, 0, 0.5): the same robot as at the origin, lifted by 0.5 m.
    _, (_, at_origin) = build((0.0, 0.0, 0.0))
    lift = state.positions - at_origin.positions
    assert lift == pytest.approx(np.tile([0.0, 0.0, 0.5], (model.particle_count, 1)), abs=1e-12)
    with pytest.raises(TypeError, match="no field 'bogus'"):
        robophi.Urdf(bogus=1)


def test_urdf_errors_name_the_file_and_line(broken_urdfs):
    bad = broken_urdfs / "bad_axis.urdf"
    with pytest.raises(robophi.SceneError) as e:
        robophi.load(bad)
    message = str(e.value)
    assert f"{bad}:12: error: joint 'shoulder': <axis xyz=\"0 0 0\"> is zero" in message
    assert message.endswith(f"{bad}: 1 error; nothing was run or written")
    with pytest.raises(robophi.SceneError) as e:
        robophi.ModelBuilder().add_urdf(robophi.Urdf(file=bad))
    assert str(e.value).startswith(f"{bad}:12: error: joint 'shoulder'")
    assert e.value.diagnostics[0]["line"] == 12
    with pytest.raises(robophi.SceneError, match="cannot read the file"):
        robophi.load(broken_urdfs / "no_such_robot.urdf")



def test_a_bad_urdf_spec_field(robots):
    spec = robophi.Urdf(file=robots / "cartpole" / "cartpole.urdf", particles_per_link=0)
    with pytest.raises(robophi.SpecError, match="particlesPerLink") as e:
        robophi.ModelBuilder().add_urdf(spec)
    assert e.value.field == "particlesPerLink"


def test_the_cli_gives_the_same_urdf_error(broken_urdfs, cli):
    bad = broken_urdfs / "bad_axis.urdf"
    with pytest.raises(robophi.SceneError) as e:
        robophi.load(bad)
    done = subprocess.run([cli, "validate", str(bad)], capture_output=True, text=True)
    assert done.returncode != 0
    assert done.stderr.strip().splitlines()[-2:] == str(e.value).splitlines()
