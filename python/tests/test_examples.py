"""The examples of docs/python.md run (short: ROBOPHI_EXAMPLE_QUICK=1)."""

import os
import pathlib
import subprocess
import sys

import pytest

pytest.importorskip("robophi", reason="the Python module was not built "
                              "(ROBOPHI_BUILD_PYTHON=OFF, or PYTHONPATH lacks build/python)")

EXAMPLES = sorted((pathlib.Path(__file__).resolve().parents[2] / "examples" / "python").glob("*.py"))


@pytest.mark.parametrize("example", EXAMPLES, ids=[e.name for e in EXAMPLES])
def test_example_runs(example):
    env = dict(os.environ, ROBOPHI_EXAMPLE_QUICK="1")
    done = subprocess.run([sys.executable, str(example)], capture_output=True, text=True, env=env,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip()
