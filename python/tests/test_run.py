"""robophi.run writes the CLI's results folder; its state hash is the CLI run's."""

import json
import subprocess

import pytest

robophi = pytest.importorskip("robophi", reason="the Python module was not built "
                              "(ROBOPHI_BUILD_PYTHON=OFF, or PYTHONPATH lacks build/python)")


def test_run_gives_the_cli_state_hash(scenes, tmp_path, cli):
    scene = scenes / "revolute_arm.json"
    result = robophi.run(scene, out=str(tmp_path / "py"), duration=0.05)
    assert result["status"] == "ok" and result["exit_code"] == 0
    summary = json.loads((tmp_path / "py" / "summary.json").read_text())
    assert summary["state_hash"] == result["state_hash"]
    assert result["state"].hash() == int(result["state_hash"], 16)
    assert (tmp_path / "py" / "replay.html").exists()
    cli_run = subprocess.run([cli, "run", str(scene), "--out", str(tmp_path / "cli"),
                              "--duration", "0.05", "--quiet"], capture_output=True, text=True)
    assert cli_run.returncode == 0, cli_run.stderr
    cli_summary = json.loads((tmp_path / "cli" / "summary.json").read_text())
    assert cli_summary["state_hash"] == result["state_hash"]
    assert sorted(p.name for p in (tmp_path / "py").iterdir()) == \
        sorted(p.name for p in (tmp_path / "cli").iterdir())


def test_run_refuses_a_folder_it_did_not_write(scenes, tmp_path):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("keep me")
    with pytest.raises(ValueError, match="robophi deletes nothing it did not write"):
        robophi.run(scenes / "pendulum.json", out=str(out), duration=0.01)
    assert (out / "notes.txt").read_text() == "keep me"


def test_run_checks_its_settings(scenes, tmp_path):
    with pytest.raises(ValueError, match="dt.*longer than the duration"):
        robophi.run(scenes / "pendulum.json", out=str(tmp_path / "x"), duration=0.01, dt=0.1,
                    step="constant")
    assert not (tmp_path / "x").exists()


def test_run_takes_a_loaded_scene(scenes, tmp_path):
    scene = robophi.load(scenes / "pendulum.json")
    result = robophi.run(scene, out=str(tmp_path / "p"), duration=0.01, step="constant")
    assert result["status"] == "ok" and result["steps"] == 100  # 0.01 s of the scene's 1e-4 s
    summary = json.loads((tmp_path / "p" / "summary.json").read_text())
    assert summary["state_hash"] == result["state_hash"]


@pytest.mark.parametrize("scene_name,duration", [("pendulum", 0.05), ("revolute_arm", 0.05),
                                                 ("ball_drop", 0.4)])
@pytest.mark.parametrize("step", ["constant", "adaptive"])
def test_a_python_world_loop_gives_the_cli_state_hash(scenes, tmp_path, cli, scene_name,
                                                      duration, step):
    """World.run from Python takes the runner's steps: the CLI's hash, bit for bit
    (scenes without robotics tasks; ball_drop bounces on the ground by 0.4 s)."""
    scene = robophi.load(scenes / f"{scene_name}.json")
    world = robophi.World(scene)
    world.run(duration, dt=scene.dt if step == "constant" else None)
    out = tmp_path / "cli"
    done = subprocess.run([cli, "run", str(scenes / f"{scene_name}.json"), "--out", str(out),
                           "--duration", str(duration), "--step", step, "--quiet"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    summary = json.loads((out / "summary.json").read_text())
    assert robophi.format_hash(world.hash()) == summary["state_hash"]
