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


def test_a_rigid_body_from_shapes_has_the_mass_properties_asked_for():
    """build::RigidBodySpec from Python: a uniform 2 kg box, 0.2 × 0.1 × 0.1 m, at (0, 0, 0.5)."""
    body = robophi.RigidBody(shapes=[robophi.Shape.box((0.2, 0.1, 0.1), xyz=(0.0, 0.0, 0.5))],
                             mass=2.0, uniform_density=True, particle_count=40)
    assert [s.kind for s in body.shapes] == ["box"]
    b = robophi.ModelBuilder()
    b.set_gravity((0, 0, 0))
    b.add(body, name="body")
    model, state = b.build()
    assert model.objects[0].kind == "rigid_body"
    m = model.masses
    p = state.positions
    assert m.sum() == pytest.approx(2.0, rel=1e-9)
    center = (m[:, None] * p).sum(axis=0) / m.sum()
    assert center.tolist() == pytest.approx([0.0, 0.0, 0.5], abs=1e-6)
    # The uniform box's inertia about z: m (a² + b²) / 12.
    d = p - center
    izz = (m * (d[:, 0] ** 2 + d[:, 1] ** 2)).sum()
    assert izz == pytest.approx(2.0 * (0.2 ** 2 + 0.1 ** 2) / 12, rel=1e-5)
    with pytest.raises(RuntimeError, match="none.stl"):
        robophi.Shape.mesh("none.stl")
