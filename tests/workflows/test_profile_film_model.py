"""Films in measured property profiles (issue 30): `indent analyze --profile --film-model`
reads a film on a substrate as such, Nix-Gao says when there is no size effect, the figure
shows both, and the piecewise profile never leaves the range of its indents."""

import json
import math

import numpy as np
import pytest

from filmscale.continuum.contact.profiles import TableProfile
from filmscale.continuum.indentation.synthetic import synthetic_curve
from filmscale.continuum.indentation.film_substrate import film_modulus
from filmscale.continuum.indentation.property_profile import property_profile
from filmscale.continuum.indentation.size_effect import nix_gao_fit
from filmscale.continuum.indentation.tips import berkovich
from filmscale.continuum.materials import DIAMOND, ElasticPlastic
from filmscale.workflows.cli import main
from filmscale.workflows.plots import plot_property_profile

T = 500e-9
SUBSTRATE = ElasticPlastic(100e9, 0.25, name="substrate")
FILM = ElasticPlastic(200e9, 0.3, name="film")
DEPTHS = T * np.geomspace(0.05, 1.0, 12)
FILM_ARGS = ["--film-thickness", "500nm", "--substrate", "100GPa,0.25", "--nu", "0.3"]


def layered_series(depths=DEPTHS):
    """E_r (diamond tip) of Berkovich indents at ``depths`` on `FILM` over `SUBSTRATE` from
    the layered solution, and H constant at 8 GPa with 2 % scatter: no size effect."""
    from filmscale.continuum.contact import coated
    if not hasattr(coated, "apparent_modulus"):
        pytest.skip("coated.apparent_modulus (the layered solution) is not in this tree yet")
    a = np.sqrt(berkovich().area(depths) / math.pi)
    e = np.array([coated.apparent_modulus(float(r), T, FILM, SUBSTRATE) for r in a])
    E_r = 1.0 / (1.0 / e + DIAMOND.compliance)
    H = 8e9 * (1 + 0.02 * np.random.default_rng(5).standard_normal(depths.size))
    return a, E_r, H


@pytest.fixture(scope="module")
def film_folder(tmp_path_factory):
    d = tmp_path_factory.mktemp("film")
    _, E_r, H = layered_series()
    for k, (h_c, e, h) in enumerate(zip(DEPTHS, E_r, H)):
        c = synthetic_curve(e, h, berkovich(), h_c=h_c, m=1.4)
        np.savetxt(d / f"i{k:02d}.csv", np.column_stack([c.h * 1e9, c.P * 1e6, c.t]),
                   delimiter=", ", header="h [nm], P [uN], t [s]", comments="")
    return d


def test_piecewise_profile_never_dips_below_its_indents():
    """A series whose unclipped least-squares line dips below every indent at its deep end
    (the issue's 67 GPa under points of about 80 GPa): one stiff shallow indent tilts the
    line. Clipped, the deep knot stays within the indents of its piece."""
    h_c = np.linspace(10e-9, 100e-9, 10)
    E_r = np.array([160e9] + [80e9] * 9)
    H = np.full(10, 5e9)
    e_p = 1.0 / (1.0 / E_r - DIAMOND.compliance)
    slope, intercept = np.polyfit(h_c, e_p, 1)          # what the fit did before
    unclipped_deep = slope * h_c[-1] + intercept
    assert unclipped_deep < e_p.min() * 0.97             # below every indent
    prof = TableProfile.from_measurements(h_c, E_r, H)
    assert np.all(prof.plane_strain_modulus >= e_p.min() * (1 - 1e-12))
    assert np.all(prof.plane_strain_modulus <= e_p.max() * (1 + 1e-12))
    assert prof.plane_strain_modulus[-1] == pytest.approx(e_p.min(), rel=1e-12)
    # the shallow knot keeps its least-squares value where that lies within the indents
    assert prof.plane_strain_modulus[0] == pytest.approx(intercept + slope * h_c[0], rel=1e-9)
    # with layer breakpoints the clip is per piece: each knot within the indents next to it
    prof = TableProfile.from_measurements(h_c, E_r, H, breakpoints=[35e-9])
    inner = (h_c >= 10e-9) & (h_c <= 100e-9)
    assert np.all(prof.plane_strain_modulus >= e_p[inner].min() * (1 - 1e-12))


def test_cli_film_model_reads_the_film_and_no_size_effect(film_folder, tmp_path, capsys):
    code = main(["indent", "analyze", str(film_folder), "--tip", "berkovich",
                 "--film-model", "exact", *FILM_ARGS, "--profile", str(tmp_path / "p.csv"),
                 "--workers", "1"])
    out = capsys.readouterr().out
    assert code == 0
    line = next(row for row in out.splitlines() if row.startswith("film (exact"))
    E = float(line.split("E = ")[1].split(" +- ")[0]) * 1e9
    # reference: FILM.E, which made the curves through the layered solution; 1 %: the
    # exact model inverts that same solution, left only with the curves' analysis error
    assert E == pytest.approx(FILM.E, rel=0.01)
    n_fit = int(np.sum(DEPTHS >= 0.1 * T))
    assert f"{n_fit} indents" in line and "residual rms" in line
    assert "Nix-Gao: h* not identified: " in out and "H = H0 (depth-independent)" in out


def test_cli_json_gains_the_film_object(film_folder, tmp_path, capsys):
    plots = tmp_path / "plots"
    code = main(["indent", "analyze", str(film_folder), "--tip", "berkovich", "--json",
                 "--film-model", "hay-crawford", *FILM_ARGS, "--plot", str(plots),
                 "--workers", "1"])
    assert code == 0
    assert (plots / "profile.png").stat().st_size > 0
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == DEPTHS.size + 1                # one per curve, then the profile's
    last = json.loads(lines[-1])
    film = last["film"]
    assert film["model"] == "hay-crawford" and film["points"] == int(np.sum(DEPTHS >= 0.1 * T))
    # reference: FILM.E of the layered solution that made the curves; 6 %: Hay-Crawford is
    # an approximation of that solution, so its own model error is allowed on top
    assert film["E"] == pytest.approx(FILM.E, rel=0.06) and film["E_std"] > 0
    assert len(film["residuals"]) == film["points"] and film["thickness"] == pytest.approx(T)
    assert film["substrate"] == {"E": 100e9, "nu": 0.25}
    assert last["nix_gao"]["identified"] is False and last["nix_gao"]["h_star"] is None
    assert last["nix_gao"]["reason"]


@pytest.mark.parametrize("argv, message", [
    (["--film-model", "king", "--substrate", "100GPa,0.25"],
     "--film-model king needs --film-thickness"),
    (["--film-model", "king", "--film-thickness", "500nm"],
     "--film-model king needs --substrate"),
    (["--film-thickness", "500nm", "--substrate", "100GPa,0.25"],
     "--film-thickness and --substrate apply to a film model: give --film-model"),
    (["--substrate", "100GPa,0.25"], "--substrate apply to a film model"),
    (["--film-model", "king", "--film-thickness", "-5nm", "--substrate", "100GPa,0.25"],
     "--film-thickness = -5e-09 m"),
])
def test_wrong_film_options_exit_2_before_any_analysis(tmp_path, capsys, argv, message):
    missing = tmp_path / "never-read.csv"           # would fail if the analysis started
    code = main(["indent", "analyze", str(missing), "--tip", "berkovich", *argv])
    err = capsys.readouterr().err
    assert code == 2
    assert message in err and "does not exist" not in err


def test_too_few_indents_in_the_models_range_is_an_input_error(film_folder, capsys):
    code = main(["indent", "analyze", str(film_folder), "--tip", "berkovich",
                 "--film-model", "king", "--film-thickness", "50um",
                 "--substrate", "100GPa,0.25", "--workers", "1"])
    assert code == 2
    assert "at least 2 indents" in capsys.readouterr().err


def test_figure_draws_the_film_model_and_a_depth_independent_hardness(tmp_path):
    a, E_r, H = layered_series()
    profile = property_profile(DEPTHS, E_r, H)
    nix_gao = nix_gao_fit(profile.h_c, profile.H)
    assert not nix_gao.identified
    film = film_modulus(DEPTHS, E_r, a, thickness=T, substrate=SUBSTRATE, model="exact")
    fig = plot_property_profile(profile, tmp_path / "profile.png", nix_gao,
                                profile.to_depth_profile(), DIAMOND.compliance,
                                title="film on substrate", film=film)
    labels = [t.get_text() for ax in fig.axes for t in ax.get_legend().get_texts()]
    assert any(s.startswith("exact: E_f = 200") for s in labels)
    assert any("fitted (" in s for s in labels)
    assert any("depth-independent H" in s for s in labels)
    assert not any("h* =" in s for s in labels)
    ax_e = fig.axes[0]
    assert "(GPa)" in ax_e.get_ylabel() and "(nm)" in ax_e.get_xlabel()
    assert (tmp_path / "profile.png").stat().st_size > 0
    # an identified size effect still draws its curve
    h = np.geomspace(20e-9, 400e-9, 12)
    ng = nix_gao_fit(h, 2e9 * np.sqrt(1 + 100e-9 / h))
    assert ng.identified
    fig = plot_property_profile(property_profile(h, np.full(12, 100e9),
                                                 2e9 * np.sqrt(1 + 100e-9 / h)), None, ng)
    labels = [t.get_text() for t in fig.axes[1].get_legend().get_texts()]
    assert any("h* = 100 nm" in s for s in labels)


def test_result_file_keeps_the_film(film_folder, tmp_path, capsys):
    import h5py
    out = tmp_path / "analysis.h5"
    code = main(["indent", "analyze", str(film_folder), "--tip", "berkovich",
                 "--film-model", "exact", *FILM_ARGS, "--out", str(out), "--workers", "1"])
    capsys.readouterr()
    assert code == 0
    with h5py.File(out, "r") as f:
        film = json.loads(f["profile"].attrs["film"])
    assert film["model"] == "exact" and film["E"] == pytest.approx(FILM.E, rel=0.01)
