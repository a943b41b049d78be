"""The example notebooks execute from top to bottom.

`examples/` lies outside `testpaths`, and a notebook is collected only with nbmake's
``--nbmake`` flag, which must not be switched on for the whole suite (it would make pytest
collect every ``.ipynb`` under the paths it is given). So this test runs nbmake on each
notebook in a subprocess of its own and asserts that every cell ran without an error: the
notebooks are documentation that breaks silently when the API they show changes.

The notebook's code runs in a Jupyter kernel, a process that pytest's ``filterwarnings =
["error"]`` does not reach; ``PYTHONWARNINGS`` carries the same rule into the kernel, so a
warning raised by a cell fails the test as it would in the suite. Deprecation warnings are
left out of that rule: the kernel machinery (ipykernel, jupyter_client, zmq) emits them
itself, and they say nothing about the notebook.
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
#: each runs in well under a minute: calibration from curves; impact maps of a layered disk as
#: xarray, pandas and a Figure; a scene from curve file to result, report and map (no MD); reading and calibrating instrument data
NOTEBOOKS = ["examples/calibration.ipynb", "examples/impact_maps.ipynb",
             "examples/scene_pipeline.ipynb", "examples/instrument_data.ipynb"]


@pytest.mark.parametrize("notebook", NOTEBOOKS)
def test_notebook_executes(notebook):
    pytest.importorskip("nbmake", reason="nbmake is in the `test` extra: pip install -e '.[test]'")
    env = dict(os.environ, PYTHONWARNINGS="error,ignore::DeprecationWarning,"
                                          "ignore::PendingDeprecationWarning")
    run = subprocess.run(
        [sys.executable, "-m", "pytest", "--nbmake", "--nbmake-timeout=120",
         "-p", "no:cacheprovider", "-q", notebook],
        cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, f"{notebook} failed under nbmake:\n{run.stdout}\n{run.stderr}"
