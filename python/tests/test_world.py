"""Stepping from Python, the arrays being views, writes booked as external work, contacts."""

import math

import numpy as np
import pytest

robophi = pytest.importorskip("robophi", reason="the Python module was not built "
                              "(ROBOPHI_BUILD_PYTHON=OFF, or PYTHONPATH lacks build/python)")
from util import single_ball  # noqa: E402


def test_free_fall_matches_the_symplectic_euler_closed_form():
    model, state = single_ball(z=1.0)
    world = robophi.World(model, state, integrator="symplectic")
    dt, n = 1e-3, 100
    for _ in range(n):
        world.step(dt)
    # Symplectic Euler: v_k = -g k dt, z_k = z0 - g dt² k (k + 1) / 2.
    assert world.time == pytest.approx(n * dt, abs=1e-15)
    assert world.step_count == n
    assert world.velocities[0, 2] == pytest.approx(-9.81 * n * dt, rel=1e-12)
    assert world.positions[0, 2] == pytest.approx(1.0 - 9.81 * dt * dt * n * (n + 1) / 2, rel=1e-12)
    assert world.forces[0].tolist() == pytest.approx([0.0, 0.0, -9.81])


def test_positions_are_views_on_the_world_memory():
    model, state = single_ball()
    world = robophi.World(model, state)
    p = world.positions
    assert p.shape == (1, 3) and p.dtype == np.float64 and p.flags.writeable
    assert np.shares_memory(p, world.positions)  # the same memory every time: no copy
    world.step(1e-3)
    assert p[0, 2] == world.positions[0, 2] < 1.0  # the held view sees the step
    del world
    assert p[0, 2] < 1.0  # the view keeps the world alive


def test_a_position_written_through_numpy_moves_the_particle_in_the_next_step():
    model, state = single_ball(z=1.0)
    world = robophi.World(model, state)
    world.step(1e-3)
    total_before = world.energy.total
    p = world.positions
    v = world.velocities[0, 2]
    p[0, 2] += 2.0  # lift the ball 2 m through the view
    e = world.energy
    # The lift is work from outside, m g Δz = 1 kg × 9.81 m/s² × 2 m, booked so
    # that the conserved total (E + dissipated − external) does not jump.
    assert e.external == pytest.approx(9.81 * 2.0, rel=1e-12)
    assert e.total == pytest.approx(total_before, abs=1e-12)
    world.step(1e-3)
    # Symplectic Euler from the written position: z = z_w + (v − g dt) dt.
    z_written = 1.0 - 9.81 * 1e-6 + 2.0
    assert world.positions[0, 2] == pytest.approx(z_written + (v - 9.81e-3) * 1e-3, rel=1e-12)


def test_a_write_through_a_temporary_view_is_booked_too():
    model, state = single_ball(z=1.0)
    world = robophi.World(model, state)
    world.step(1e-3)
    v_before = world.velocities[0, 2]
    world.velocities[0] = (1.0, 0.0, 0.0)  # the view is gone at once
    world.step(1e-2)
    assert world.positions[0, 0] == pytest.approx(1e-2)
    # ½ m (|v_new|² − |v_old|²) given from outside.
    assert world.energy.external == pytest.approx(0.5 * (1.0 - v_before ** 2), rel=1e-9)


def test_a_non_finite_write_raises_and_changes_nothing():
    model, state = single_ball(z=1.0)
    world = robophi.World(model, state)
    before = world.hash()
    world.positions[0, 1] = math.nan
    with pytest.raises(ValueError, match=r"setPosition: position = \(0, nan, 1\) must be finite"):
        world.step(1e-3)
    assert world.hash() == before
    world.step(1e-3)  # and the world goes on


def test_state_copies_snapshots_and_set_state_are_exact():
    model, state = single_ball()
    world = robophi.World(model, state)
    saved = world.snapshot()
    copy = world.state
    p = world.positions
    for _ in range(10):
        world.step(1e-3)
    after = world.hash()
    world.restore(saved)
    assert world.hash() == copy.hash() == saved.state.hash()
    for _ in range(10):
        world.step(1e-3)
    assert world.hash() == after
    world.set_state(copy)
    assert world.time == 0.0 and p[0, 2] == 1.0  # the held view still sees the world


def test_advance_and_run_with_a_callback(scenes):
    scene = robophi.load(scenes / "ball_drop.json")
    world = robophi.World(scene)
    assert world.integrator == "verlet"  # the scene's default
    dt = world.advance()
    assert 0 < dt <= 1e-4 * 2
    times, heights = [], []

    def record(w):
        times.append(w.time)
        heights.append(w.positions[0, 2])
        return w.time < 0.25  # False ends the run

    held = world.positions  # a view taken before adaptive steps (which restore snapshots)
    steps = world.run(1.0, callback=record)
    assert np.shares_memory(held, world.positions) and held[0, 2] == heights[-1]
    assert steps == len(times) and times[-1] >= 0.25 > times[-2]
    assert all(b > a for a, b in zip(times, times[1:]))
    # The ball falls freely until it touches the ground at z = r = 0.05 m.
    assert heights[-1] == pytest.approx(0.55 - 0.5 * 9.81 * times[-1] ** 2, abs=1e-4)


def test_run_with_constant_steps_lands_on_the_duration():
    model, state = single_ball()
    world = robophi.World(model, state)
    assert world.run(0.0105, dt=1e-3) == 11
    assert world.time == pytest.approx(0.0105, abs=1e-15)


def test_contacts_are_a_structured_array(scenes):
    world = robophi.World(robophi.load(scenes / "ball_drop.json"))
    world.integrator = "symplectic"  # the evaluation then sees the state's velocity
    assert world.contacts.shape == (0,)
    # Falls 0.5 m (0.319 s) and stops at its first contact with the ground.
    world.run(1.0, callback=lambda w: len(w.contacts) == 0)
    assert 0.3 < world.time < 0.33
    c = world.contacts
    assert c.dtype.names == ("a", "other", "environment", "sliding", "depth", "normal",
                             "normal_force", "friction_force")
    assert len(c) == 1 and c["a"][0] == 0 and c["other"][0] == -1 and c["environment"][0] == 0
    assert c["depth"][0] < 0
    assert c["normal"][0].tolist() == pytest.approx([0.0, 0.0, 1.0])
    # MODEL §3.1: F_n = −κ_c d − μ_c ḋ (κ_c = 1e6 N/m, μ_c = 28.3 N·s/m), ḋ = v_z.
    expected = -1e6 * c["depth"][0] - 28.3 * world.velocities[0, 2]
    assert c["normal_force"][0] == pytest.approx(max(expected, 0.0), rel=1e-9)
    assert world.forces[0, 2] == pytest.approx(c["normal_force"][0] - 0.2 * 9.81, rel=1e-9)


def test_apply_impulse_changes_a_free_particle_by_p_over_m_and_books_its_work():
    model, state = single_ball(z=1.0, gravity=(0.0, 0.0, 0.0), mass=2.0)
    world = robophi.World(model, state)
    world.step(1e-3)
    world.book_external_work()
    world.apply_impulse(0, (1.0, 2.0, -3.0))
    assert world.velocities[0].tolist() == pytest.approx([0.5, 1.0, -1.5], rel=1e-15)
    # ½ m |Δv|² from rest: ½ 2 (0.25 + 1 + 2.25) = 3.5 J, external work.
    assert world.book_external_work() == pytest.approx(3.5, rel=1e-12)
