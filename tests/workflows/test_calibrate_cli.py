"""`filmscale calibrate`: JSON keys, the film-on-substrate route, tip checks and exit codes,
against the parameters that generated the curves."""

import json

import numpy as np
import pytest

from filmscale.workflows.cli import main
from tests.helpers import curves as tc
from tests.helpers import film_curves as tl
from tests.helpers.curves import write_curves

KEYS = {"E", "E_std", "sigma_y", "sigma_y_std", "n", "cross_check_rms", "passed"}


def test_film_on_substrate_from_the_command_line(tmp_path, capsys):
    """Film 100 GPa / 2 GPa on a 3 x stiffer substrate (1 % noise): E within 3 % and
    sigma_y within 10 % with the substrate stated; the half-space call attributes the
    substrate to the film and its cross-scale check fails at the default 10 %."""
    curves, sub = tl.film_curves(1 / 3, np.random.default_rng(1))
    path = write_curves(tmp_path / "film.h5", curves)
    substrate = f"{sub.E!r},{sub.nu!r},{sub.sigma_y!r}"
    assert main(["calibrate", path, "--tip-material", "rigid", "--nu", "0.3",
                 "--film-thickness", "50e-9", "--substrate", substrate, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert KEYS <= set(out)
    assert abs(out["E"] / tl.E_FILM - 1) < 0.03 and abs(out["sigma_y"] / tl.SY_FILM - 1) < 0.1
    assert out["passed"] and out["cross_check_rms"] < 0.02 and out["n"] is None
    assert main(["calibrate", path, "--tip-material", "rigid", "--nu", "0.3", "--json"]) == 0
    alone = json.loads(capsys.readouterr().out)
    assert alone["E"] / tl.E_FILM - 1 > 0.2 and not alone["passed"]


def test_sharp_curves_give_n(tmp_path, capsys):
    """Dao's forward curve (Al 7075-like, n = 0.122) through the reverse analysis."""
    _, curve = tc.synthetic_sharp_curve(70.1e9, 0.33, 0.5e9, 0.122, 1e-6)
    path = write_curves(tmp_path / "berk.h5", [curve])
    assert main(["calibrate", path, "--nu", "0.33", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["route"] == "sharp" and out["E"] == pytest.approx(70.1e9, rel=0.05)


@pytest.mark.parametrize("args, message", [
    (["--tip", "sphere:5um"], "looks sharp"),
    (["--film-thickness", "5e-8"], "--film-thickness and --substrate go together"),
    (["--tip", "berkovich", "--film-thickness", "5e-8", "--substrate", "300e9,0.25"],
     "Dao's reverse analysis of sharp tips holds for a half-space"),
    (["--nu", "0.7"], "nu = 0.7"),
    (["--contact-zero", "fit"], "has no zero to fit"),
])
def test_bad_calls_exit_2_with_one_line(tmp_path, capsys, args, message):
    _, curve = tc.synthetic_sharp_curve(70.1e9, 0.33, 0.5e9, 0.122, 1e-6)
    path = write_curves(tmp_path / "berk.h5", [curve])
    assert main(["calibrate", path, *args]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


def test_contact_zero_fit_from_the_command_line(tmp_path, capsys):
    """An MD-like curve whose depths are 8 % of the pop-in depth off their zero: with
    --contact-zero fit, E within 3 % of the generating value; without it, more than 5 % off
    (the same oracle as tests/continuum/test_elastic_segment.py, through the CLI)."""
    from tests.helpers import md_like_curves as te
    dy = float(te.LAW.first_yield(te.R, te.E_STAR, te.SY, te.NU).approach)
    curve = te.md_like_curve(np.random.default_rng(5), offset=0.48 * dy)
    path = write_curves(tmp_path / "md.h5", [curve])
    common = ["calibrate", path, "--tip-material", "rigid", "--nu", str(te.NU), "--json"]
    assert main([*common, "--contact-zero", "fit"]) == 0
    assert json.loads(capsys.readouterr().out)["E"] == pytest.approx(te.E, rel=0.03)
    assert main([*common, "--contact-zero", "fixed"]) == 0
    assert abs(json.loads(capsys.readouterr().out)["E"] / te.E - 1) > 0.05
