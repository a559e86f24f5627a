"""The examples of docs/python.md's sections "The robotics toolkit beside MuJoCo's names"
and "Sensors and vector I/O" run, each section in order and in one namespace, from a
folder where robots/ is the shared robot descriptions and tests/ this checkout's tests
(for tests/build/mjcf/arm.xml)."""

import os
import re

import pytest

from conftest import ROBOTS, SOURCE_DIR

robophi = pytest.importorskip("robophi", reason="the Python module was not built "
                              "(ROBOPHI_BUILD_PYTHON=OFF, or PYTHONPATH lacks build/python)")

SECTION = "## The robotics toolkit beside MuJoCo's names"
SENSORS = "## Sensors and vector I/O"


def _section_blocks(title=SECTION):
    text = (SOURCE_DIR / "docs" / "python.md").read_text()
    start = text.index(title)
    end = text.find("\n## ", start + len(title))
    section = text[start:end if end >= 0 else len(text)]
    return re.findall(r"```python\n(.*?)```", section, flags=re.S)


def test_the_section_has_an_example_per_piece():
    assert len(_section_blocks()) >= 4
    assert len(_section_blocks(SENSORS)) >= 3


def test_the_sensor_examples_run(tmp_path, monkeypatch):
    if not (ROBOTS / "kuka_iiwa" / "model.urdf").exists():
        pytest.skip(f"the shared robots are not at {ROBOTS} (set ROBOPHI_ROBOTS_DIR)")
    (tmp_path / "robots").symlink_to(ROBOTS)
    monkeypatch.chdir(tmp_path)
    namespace = {}
    for number, block in enumerate(_section_blocks(SENSORS)):
        exec(compile(block, f"docs/python.md sensors example {number + 1}", "exec"), namespace)


def test_the_toolkit_examples_run(tmp_path, monkeypatch):
    if not (ROBOTS / "kuka_iiwa" / "model.urdf").exists():
        pytest.skip(f"the shared robots are not at {ROBOTS} (set ROBOPHI_ROBOTS_DIR)")
    (tmp_path / "robots").symlink_to(ROBOTS)
    (tmp_path / "tests").symlink_to(SOURCE_DIR / "tests")
    monkeypatch.chdir(tmp_path)
    namespace = {}
    for number, block in enumerate(_section_blocks()):
        if "mjcf" in block and not robophi._robophi._mjcf_available():
            pytest.skip("robophi was built without libmujoco-dev (MJCF import)")
        exec(compile(block, f"docs/python.md example {number + 1}", "exec"), namespace)
