"""The import contracts of docs/architecture.md: core is a leaf kernel; continuum is pure and
flows calibration -> indentation -> contact; workflows -> md -> potentials."""

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_import_linter_contracts_are_kept():
    # contracts live in pyproject.toml [tool.importlinter]
    lint = Path(sys.executable).with_name("lint-imports")
    done = subprocess.run([str(lint)], cwd=ROOT, capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "broken" in done.stdout and "0 broken" in done.stdout


def test_continuum_imports_without_lammps_or_plotting():
    code = ("import sys, filmscale.continuum; "
            "print(sorted(m for m in sys.modules if m.split('.')[0] in "
            "('lammps', 'matplotlib', 'ase', 'MDAnalysis', 'mpi4py')))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True)
    assert done.stdout.strip() == "[]"


def test_the_four_scales_are_importable_namespaces():
    import filmscale.continuum
    import filmscale.md
    import filmscale.potentials
    import filmscale.workflows

    for module, folder in ((filmscale.continuum, "continuum"), (filmscale.md, "md"),
                           (filmscale.potentials, "potentials"),
                           (filmscale.workflows, "workflows")):
        assert Path(module.__file__).parent == ROOT / folder
