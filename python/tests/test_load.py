"""Loading scenes and reading the model: arrays are views, objects and joints by name."""

import numpy as np
import pytest

robophi = pytest.importorskip("robophi", reason="the Python module was not built "
                              "(ROBOPHI_BUILD_PYTHON=OFF, or PYTHONPATH lacks build/python)")


def test_load_scene_model_and_state(scenes):
    scene = robophi.load(scenes / "revolute_arm.json")
    assert scene.name == "revolute arm"
    assert scene.duration == 2.0 and scene.dt == 1e-4 and scene.integrator == "symplectic"
    model = scene.model
    assert model.particle_count == 12
    masses = model.masses
    assert masses.shape == (12,) and masses.dtype == np.float64
    assert masses[0] == 1.0 and masses[3] == 0.125
    assert not masses.flags.writeable          # the model is read-only
    assert np.shares_memory(masses, model.masses)  # a view, not a copy
    assert np.all(model.inverse_masses[:3] == 0.0)  # the fixed base
    ls = model.linear_springs
    assert ls.shape == (34,) and ls.dtype.names == ("a", "b", "rest_length", "stiffness", "damping")
    assert ls["stiffness"][0] == 5e4 and ls["rest_length"][0] == pytest.approx(0.25)
    assert model.joint_springs["stiffness"].tolist() == [100.0, 40.0]
    assert [j.name for j in model.joints] == ["shoulder", "elbow"]
    assert model.joint("elbow") == 1
    link2 = model.object("link2")
    assert (link2.first_particle, link2.particle_count) == (8, 4)
    state = scene.initial
    assert state.positions.shape == (12, 3)
    assert tuple(state.positions[link2.particles][1]) == (1.0, 0.0, 1.0)


def test_unknown_names_raise_key_error(scenes):
    model = robophi.load(scenes / "revolute_arm.json").model
    with pytest.raises(KeyError, match="no joint named 'wrist'.*shoulder, elbow"):
        model.joint("wrist")
    with pytest.raises(KeyError, match="no object named 'link3'"):
        model.object("link3")


def test_builder_makes_a_model_without_json():
    b = robophi.ModelBuilder()
    rubber = b.add_material(robophi.Material("rubber", contact_stiffness=1e5, contact_damping=30,
                                             static_friction=0.8, kinetic_friction=0.6))
    b.add_plane()
    first = b.add(robophi.Box(center=(0, 0, 0.06), size=(0.1, 0.1, 0.1), cells=(2, 2, 2),
                              mass=0.5), name="box", material=rubber)
    arm = b.add(robophi.Arm(base=(0.5, 0, 0.2), links=[0.3, 0.2], joint_stiffness=5.0), name="arm")
    model, state = b.build()
    assert first == (0, 0, 8)
    assert arm[0] == 1 and arm[1] == 8
    assert model.particle_count == 8 + arm[2]
    assert [j.name for j in model.joints] == ["arm.j1", "arm.j2"]
    assert model.materials[rubber].name == "rubber"
    assert model.masses[:8].sum() == pytest.approx(0.5)
    world = robophi.World(model, state)
    assert world.joint_positions.tolist() == pytest.approx([0.0, 0.0], abs=1e-12)  # straight: q = 0
    assert world.joint_values.tolist() == pytest.approx([j.zero for j in model.joints], abs=1e-12)


def test_spec_keywords_are_checked():
    with pytest.raises(TypeError, match="has no field 'centre'"):
        robophi.Box(centre=(0, 0, 0))
    box = robophi.Box(size=(0.2, 0.1, 0.1), cells=(3, 1, 1))
    assert box.size == (0.2, 0.1, 0.1) and box.cells == [3, 1, 1]


def test_urdf_waits_for_the_importer(tmp_path):
    if hasattr(robophi._robophi, "_load_urdf"):
        pytest.skip("this robophi has the URDF importer")
    with pytest.raises(NotImplementedError, match="no URDF importer"):
        robophi.load(tmp_path / "robot.urdf")
