"""Shared fixtures of the Python package's tests (docs/python.md "Tests").

The tests import robophi from PYTHONPATH (build/python when ctest runs them) and
are skipped, with a message, when the module was not built."""

import os
import pathlib

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("ROBOPHI_SOURCE_DIR",
                                         pathlib.Path(__file__).resolve().parents[2]))
SCENES = SOURCE_DIR / "scenes"


def _robots_dir():
    """The shared robot descriptions, as the C++ tests find them (tests/CMakeLists.txt's
    ROBOPHI_ROBOTS_DIR): ../shared/robots beside the checkout, or ../../shared/robots
    beside a worktree."""
    if "ROBOPHI_ROBOTS_DIR" in os.environ:
        return pathlib.Path(os.environ["ROBOPHI_ROBOTS_DIR"])
    for up in (SOURCE_DIR.parent, SOURCE_DIR.parent.parent):
        if (up / "shared" / "robots").is_dir():
            return up / "shared" / "robots"
    return SOURCE_DIR.parent / "shared" / "robots"


ROBOTS = _robots_dir()


@pytest.fixture
def scenes():
    return SCENES


@pytest.fixture
def cli():
    """The robophi program of the same build (ROBOPHI_BINARY), or skip."""
    binary = os.environ.get("ROBOPHI_BINARY")
    if not binary or not os.path.exists(binary):
        pytest.skip("ROBOPHI_BINARY (the robophi program of this build) is not set")
    return binary


@pytest.fixture
def robots():
    """The shared robot descriptions (URDF files), or skip."""
    if not (ROBOTS / "cartpole" / "cartpole.urdf").exists():
        pytest.skip(f"the shared robots are not at {ROBOTS} (set ROBOPHI_ROBOTS_DIR)")
    return ROBOTS


@pytest.fixture
def broken_urdfs():
    return SOURCE_DIR / "tests" / "urdf" / "broken"
