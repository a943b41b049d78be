"""Particle scratch of bonded layers (ULSPH): the input's layers and boundaries, refusals, and
the chapter 7 observation on two two-layer targets (LAMMPS).

The observation (the seed dissertation's chapter 7): under a hard thin film on a softer layer
the lower layer is plastically deformed over a region wider than the groove seen at the
surface; under a soft film on a harder layer it is the other way round."""

import copy
import re

import pytest

from filmscale.core.errors import InputError
from filmscale.md.particle_scratch import PRESETS, scratch_input, spec_from_mapping
from filmscale.md.particle_scratch_run import analyze_scratch, run_scratch
from filmscale.workflows.cli import main
from filmscale.workflows.scratch_plots import particle_scratch_figure_data, plot_scratch

HARD = {"E": 200e9, "nu": 0.25, "sigma_y": 10e9, "density": 7800.0, "name": "hard"}
SOFT = {"E": 70e9, "nu": 0.3, "sigma_y": 1.5e9, "density": 2700.0, "name": "soft"}


def two_layer(film: dict, substrate: dict, thickness: float, spacing: float = 1.25e-7,
              depth: float = 1.5e-7, width: float = 1.25e-6, block_depth: float = 1.5e-6):
    return {"name": "two-layer", "method": "ulsph", "tip": "sphere:1um",
            "target": {"substrate": dict(substrate), "films": [{"thickness": thickness, **film}]},
            "grid": {"spacing": spacing, "width": width, "depth": block_depth},
            "scratch": {"depth": depth, "length": 1e-6, "speed": 100.0, "load_speed": 50.0,
                        "relax_time": 1e-9, "frames": 0}}


def test_layered_input_bonds_the_film_and_holds_the_sides():
    spec = spec_from_mapping(two_layer(HARD, SOFT, 3.75e-7))
    text = scratch_input(spec)
    assert "create_box 2 world" in text and "create_atoms 2 region block" in text
    # the film is the planes z = 0, -1, -2 spacings (0.125 um): bounds half a spacing off them
    film = re.search(r"region layer1 block INF INF INF INF (\S+) (\S+) units box", text)
    assert float(film.group(1)) == pytest.approx(-0.3125) and \
        float(film.group(2)) == pytest.approx(0.0625)
    assert "set region layer1 type 1" in text
    assert re.search(r"pair_coeff 1 1 \*COMMON .* \*STRENGTH_LINEAR_PLASTIC", text)
    assert "pair_coeff 1 2 *CROSS" in text
    assert "fix integration target smd/integrate_ulsph" in text
    # both x ends and the far y side roll (zero normal velocity); the mirror plane too
    assert "fix roll_x x_ends smd/setvel 0 NULL NULL" in text
    assert "fix roll_y y_far smd/setvel NULL 0 NULL" in text
    assert "fix sym_y sym_y smd/setvel NULL 0 NULL" in text
    # the penalty stiffness is set by the stiffest material (the film): 100 E*
    e_star = HARD["E"] / (1 - HARD["nu"] ** 2) / 1e9           # GPa, particle units
    K = float(re.search(r"fix ind_interior interior indent (\S+)", text).group(1))
    assert K == pytest.approx(100 * e_star, rel=1e-6)


@pytest.mark.parametrize("change, message", [
    (lambda d: d.update(method="tlsph"), "method = 'ulsph'"),
    (lambda d: d["target"]["films"][0].update(thickness=1.2e-7), "films[0].thickness"),
    (lambda d: d["grid"].update(depth=5e-7), "grid.depth"),
    (lambda d: d.update(method="peri"), "method = 'peri'"),
])
def test_layered_spec_refusals(change, message):
    data = two_layer(HARD, SOFT, 3.75e-7)
    change(data)
    with pytest.raises(InputError, match=re.escape(message)):
        spec_from_mapping(data)


def test_quick_preset_is_the_hard_film_case():
    data = copy.deepcopy(PRESETS["quick"])
    spec = spec_from_mapping(data)
    film, substrate = spec.target.materials
    assert spec.method == "ulsph" and film.material.E > substrate.material.E
    assert film.material.sigma_y > substrate.material.sigma_y


# ---- the chapter 7 observation (LAMMPS) ----------------------------------------------------

def lower_zone_against_groove(tmp_path, film, substrate, thickness, depth, width, spacing):
    """(the lower layer's plastic-zone width, the groove width, the analysis) of a scratch;
    its figure checked on the way."""
    spec = spec_from_mapping(two_layer(film, substrate, thickness, spacing=spacing,
                                       depth=depth, width=width))
    run = run_scratch(spec, tmp_path / "run")
    a = analyze_scratch(run)
    zones = {z.layer: z for z in a.damage}
    assert set(zones) == {film["name"], substrate["name"]}
    # a plastic groove has a scratch hardness: Williams' 8 F_n / (pi w^2), written out here
    assert a.scratch_hardness == pytest.approx(8 * a.normal_force_mean /
                                               (3.141592653589793 * a.groove_width**2))
    check_figure(run, a, tmp_path / "scratch.png")
    return zones[substrate["name"]], a.groove_width, a


def check_figure(run, a, path):
    """The figure's data: the section mirrored about the groove axis, the interface at the
    film's thickness, one box per yielded layer as wide as its zone; the figure drawn."""
    data = particle_scratch_figure_data(run, a)
    assert sorted(data.section_y) == pytest.approx(sorted(-data.section_y), abs=1e-12)
    assert data.interfaces == pytest.approx((run.spec.target.films[0][0],))
    zones = {z.layer: z for z in a.damage if z.particles}
    assert {b.layer for b in data.damage} == set(zones)
    for b in data.damage:
        assert b.width == pytest.approx(zones[b.layer].width)
    fig = plot_scratch(data, path)
    labels = [ax.get_xlabel() for ax in fig.axes[:4]] + [ax.get_ylabel() for ax in fig.axes[:4]]
    assert "sliding distance (um)" in labels and "force (mN)" in labels
    assert path.stat().st_size > 10_000


def check_hard_film(zone, groove, a, spacing):
    # a groove, a zone inside the block: off its rollers and the free layer above its base
    assert a.groove_depth > 0.3 * 1.5e-7 and groove > 0
    assert zone.width / 2 < 1.75e-6 - 1.5 * spacing and zone.depth < 1.5e-6 - 1.5 * spacing
    # the lower layer is plastic over a region wider than the groove
    assert zone.width > groove, (zone, groove)


def check_soft_film(zone, groove, a):
    assert a.groove_depth > 0.2 * 1e-7 and groove > 0
    assert zone.width < groove, (zone, groove)


CASES = ["hard film on a softer layer", "soft film on a harder layer"]


def check_case(tmp_path, case: str, dx: float, hard_planes: int, soft_planes: int):
    """The hard film (0.15 R deep, 1.75 um block) or the soft one (0.1 R, 1.5 um)."""
    if case.startswith("hard"):
        zone, groove, a = lower_zone_against_groove(tmp_path, HARD, SOFT, hard_planes * dx,
                                                    1.5e-7, 1.75e-6, dx)
        check_hard_film(zone, groove, a, dx)
    else:
        zone, groove, a = lower_zone_against_groove(tmp_path, SOFT, HARD, soft_planes * dx,
                                                    1e-7, 1.5e-6, dx)
        check_soft_film(zone, groove, a)


@pytest.mark.parametrize("case", CASES)
def test_lower_layer_zone_against_the_groove_coarse(tmp_path, case):
    """R/6 (3 480 and 2 500 particles, about 30 s and 20 s)."""
    check_case(tmp_path, case, 1e-6 / 6, 2, 3)


@pytest.mark.slow
@pytest.mark.parametrize("case", CASES)
def test_lower_layer_zone_against_the_groove_fine(tmp_path, case):
    """R/8 (7 215 and 5 577 particles, about 100 s and 70 s): the hard case is the quick
    preset's target."""
    check_case(tmp_path, case, 1.25e-7, 3, 4)


def test_cli_refuses_a_layered_tlsph_scratch(tmp_path, capsys):
    path = tmp_path / "spec.toml"
    path.write_text(
        'name = "x"\nmethod = "tlsph"\ntip = "sphere:1um"\n[target.substrate]\nE = 70e9\n'
        'nu = 0.3\n[[target.films]]\nthickness = 3.75e-7\nE = 200e9\nnu = 0.25\n[grid]\n'
        'spacing = 1.25e-7\nwidth = 1.25e-6\ndepth = 1.5e-6\n[scratch]\ndepth = 1.5e-7\n'
        'length = 1e-6\n')
    assert main(["particles", "scratch", str(path), "--out", str(tmp_path / "run")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "method = 'ulsph'" in err[0]
