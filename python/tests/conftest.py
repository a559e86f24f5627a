"""Shared fixtures of the Python package's tests (docs/python.md "Tests").

The tests import robophi from PYTHONPATH (build/python when ctest runs them) and
are skipped, with a message, when the module was not built."""

import os
import pathlib

import pytest

SOURCE_DIR = pathlib.Path(os.environ.get("ROBOPHI_SOURCE_DIR",
                                         pathlib.Path(__file__).resolve().parents[2]))
SCENES = SOURCE_DIR / "scenes"


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
