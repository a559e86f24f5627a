"""rollout: many worlds of one model in parallel, bit-identical whatever the thread count."""

import numpy as np
import pytest

robophi = pytest.importorskip("robophi", reason="the Python module was not built "
                              "(ROBOPHI_BUILD_PYTHON=OFF, or PYTHONPATH lacks build/python)")
from util import vertical_arm  # noqa: E402


def arm_rollout_inputs(worlds=6, steps=40):
    model, state = vertical_arm()
    rng = np.random.default_rng(7)
    controls = rng.uniform(-0.5, 0.5, size=(worlds, steps, len(model.joints)))
    states = []
    for w in range(worlds):
        s = state.copy()
        s.velocities[-1] = (0.0, 0.0, 0.01 * w)  # each world starts a little differently
        states.append(s)
    return model, states, controls


def test_threads_do_not_change_any_bit():
    model, states, controls = arm_rollout_inputs()
    one = robophi.rollout(model, states, controls, dt=1e-3, substeps=10, threads=1)
    two = robophi.rollout(model, states, controls, dt=1e-3, substeps=10, threads=2)
    three = robophi.rollout(model, states, controls, dt=1e-3, substeps=10, threads=3)
    assert one["hashes"] == two["hashes"] == three["hashes"]
    assert len(set(one["hashes"])) == len(states)  # the worlds differ
    assert np.array_equal(one["joint_positions"], two["joint_positions"])
    for a, b in zip(one["states"], two["states"]):
        assert np.array_equal(a.positions, b.positions)


def test_a_rollout_world_equals_a_python_loop_of_single_steps():
    model, states, controls = arm_rollout_inputs(worlds=2, steps=20)
    result = robophi.rollout(model, states, controls, dt=1e-3, substeps=10, threads=2)
    world = robophi.World(model, states[1])
    trace = []
    for k in range(20):
        world.set_joint_targets(controls[1, k])
        for _ in range(10):
            world.step(1e-4)
        trace.append(world.joint_positions)
    assert world.hash() == result["hashes"][1]
    assert np.array_equal(np.array(trace), result["joint_positions"][1])


def test_hand_grasp_copies_adaptive(scenes):
    scene = robophi.load(scenes / "hand_grasp.json")
    one = robophi.rollout(scene.model, [scene.initial] * 3, steps=4, dt=2e-3, threads=1,
                          integrator=scene.integrator, adaptive=robophi.AdaptiveSettings())
    two = robophi.rollout(scene.model, [scene.initial] * 3, steps=4, dt=2e-3, threads=2,
                          integrator=scene.integrator, adaptive=robophi.AdaptiveSettings())
    assert one["hashes"] == two["hashes"]
    assert len(set(one["hashes"])) == 1  # identical worlds end identically
    assert one["states"][0].time == pytest.approx(8e-3, abs=1e-12)


def test_rollout_checks_its_arguments():
    model, states, controls = arm_rollout_inputs(worlds=2, steps=5)
    with pytest.raises(ValueError, match="controls have 1 targets per step; the model has 2 joints"):
        robophi.rollout(model, states, np.zeros((5, 1)), dt=1e-3)
    with pytest.raises(ValueError, match="2 initial states but controls for 3 worlds"):
        robophi.rollout(model, states, np.zeros((3, 5, 2)), dt=1e-3)
    with pytest.raises(ValueError, match="give steps, or controls"):
        robophi.rollout(model, states, dt=1e-3)


def test_one_state_and_one_control_sequence_for_every_world():
    model, state = vertical_arm()
    controls = np.linspace(0.0, 0.3, 10)[:, None].repeat(2, axis=1)  # (steps, joints)
    out = robophi.rollout(model, [state, state], controls, dt=1e-3, substeps=10, threads=2)
    assert out["joint_positions"].shape == (2, 10, 2)
    assert out["hashes"][0] == out["hashes"][1]
    assert len(out["thread_cpu_seconds"]) == 2
