"""Errors as Python exceptions, with the CLI's messages."""

import subprocess

import pytest

robophi = pytest.importorskip("robophi", reason="the Python module was not built "
                              "(ROBOPHI_BUILD_PYTHON=OFF, or PYTHONPATH lacks build/python)")
from util import single_ball  # noqa: E402

BROKEN = """{
  "robophi": 1,
  "objects": [
    {"name": "b", "type": "ball", "center": [0, 0, 0], "radius": -1, "mass": 1},
    {"name": "c", "type": "bal", "center": [0, 0, 1], "radius": 0.1, "mass": 1}
  ]
}
"""


def test_scene_errors_carry_the_cli_messages(tmp_path, cli):
    path = tmp_path / "broken.json"
    path.write_text(BROKEN)
    with pytest.raises(robophi.SceneError) as caught:
        robophi.load(path)
    error = caught.value
    assert isinstance(error, ValueError) and isinstance(error, robophi.Error)
    lines = str(error).splitlines()
    assert lines[0].startswith(f"{path}:4:")  # file:line:column
    assert lines[-1] == f"{path}: {len(error.diagnostics)} errors; nothing was run or written"
    assert error.diagnostics[0]["line"] == 4 and error.diagnostics[0]["pointer"].startswith("/objects/0")
    # The same lines as the command line's.
    cli_run = subprocess.run([cli, "validate", str(path)], capture_output=True, text=True)
    assert cli_run.returncode == 2
    cli_lines = [line for line in cli_run.stderr.splitlines() if line.startswith(str(path))]
    assert cli_lines == lines


def test_a_missing_scene_file(tmp_path):
    with pytest.raises(robophi.SceneError, match="nothing was run or written"):
        robophi.load(tmp_path / "none.json")


def test_api_errors_map_to_value_and_index_errors():
    model, state = single_ball()
    world = robophi.World(model, state)
    with pytest.raises(IndexError, match=r"World::setPosition: particle 5 does not exist \(there are 1\)"):
        world.set_position(5, (0, 0, 0))
    with pytest.raises(ValueError, match=r"World::step: dt = -1 s must be > 0 and finite"):
        world.step(-1.0)
    with pytest.raises(ValueError, match="integrator 'rk4'"):
        robophi.World(model, state, integrator="rk4")
    with pytest.raises(IndexError, match="joint 0 does not exist"):
        world.set_joint_target(0, 1.0)


def test_spec_errors_name_the_field():
    b = robophi.ModelBuilder()
    with pytest.raises(robophi.SpecError, match="'mass' must be > 0") as caught:
        b.add(robophi.Box(mass=-2.0), name="box")
    assert caught.value.field == "mass" and caught.value.spec == "BoxSpec"
    assert isinstance(caught.value, ValueError)


def test_a_diverging_world_raises_diverged_error():
    b = robophi.ModelBuilder()
    b.set_gravity((0, 0, 0))
    b.add(robophi.Rope(start=(0, 0, 0), end=(1, 0, 0), particles=3, mass=1.0), name="rope",
          stiffness=1e12)
    model, state = b.build()
    world = robophi.World(model, state)
    world.positions[1, 1] = 0.1
    with pytest.raises(robophi.DivergedError, match="made the state non-finite"):
        for _ in range(10000):
            world.step(1e-2)
