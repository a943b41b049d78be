"""Particle-model indenters beyond the sphere and the cone, without LAMMPS: the half model,
the three-sided pyramids built face by face, the sphero-conical tip, and the elastic closed
forms their runs are compared with."""

import math
import re

import numpy as np
import pytest

from filmscale.continuum.indentation.tips import BERKOVICH_AREA, CUBE_CORNER_AREA, parse_tip
from filmscale.continuum.materials import ElasticPlastic
from filmscale.core.errors import InputError
from filmscale.md.lammps_input import check_input
from filmscale.md.particle_inputs import K_FACTOR, input_text
from filmscale.continuum.contact.hertz import hertz_force
from filmscale.md.particle_run import (ParticleRun, analyze_indent, block_elastic_force,
                                       sneddon_force, sphero_conical_force)
from filmscale.md.particles import (Grid, IndentLoading, ParticleIndentSpec, ParticleMaterial,
                                    ParticleTarget, contact_radius)
from filmscale.md.lammps_units import si_to_lammps

AL = ParticleMaterial(ElasticPlastic(70e9, 0.3, name="Al"), 2700.0)
DX = 5e-8     # the example spec's: a 0.12 um indent is 2.4 spacings deep


def spec(tip="berkovich", grid=None, depth=1.2e-7, method="tlsph"):
    return ParticleIndentSpec(name="tip", method=method, target=ParticleTarget(AL), tip=tip,
                              loading=IndentLoading(depth, 30.0),
                              grid=grid or Grid(DX, 1.2e-6, 1.2e-6, quarter=False, half=True))


def face_normals(text: str) -> np.ndarray:
    """The outward face normals N_k of ``variable sK atom nx*x+ny*y+nz*(z-v_apex)``."""
    rows = re.findall(r"variable s\d atom (\S+)\*x\+(\S+)\*y\+(\S+)\*\(z-v_apex\)", text)
    return np.array(rows, dtype=float)


def test_half_grid_counts_and_symmetry():
    g = Grid(DX, 1.2e-6, 1.0e-6, quarter=False, half=True)
    assert g.counts() == (25, 49, 21)
    assert g.symmetry_factor == 2.0
    with pytest.raises(InputError, match="grid.quarter = true and grid.half = true"):
        Grid(DX, 1.2e-6, 1.0e-6, quarter=True, half=True)


@pytest.mark.parametrize("kwargs, match", [
    (dict(grid=Grid(DX, 1.2e-6, 1.2e-6, quarter=True)), "no quarter symmetry"),
    (dict(tip="berkovich:5nm"), "sharp pyramids only"),
    (dict(tip="flat:1um"), "particle models take"),
    (dict(grid=Grid(1e-7, 1.2e-6, 1.2e-6, quarter=False, half=True)), "too coarse for a "
     "berkovich indent"),
    (dict(grid=Grid(DX, 1.2e-6, 1.2e-6, quarter=False, half=True), method="peri",
          tip="cone:70.3", depth=4e-7), "grid.half = true: the peridynamic model"),
    # the edge radius at 0.12 um is 0.52 um, so a 0.9 um block is under twice it
    (dict(grid=Grid(DX, 0.9e-6, 1.2e-6, quarter=False, half=True)), "grid.width"),
])
def test_tip_and_grid_refusals_name_the_parameter(kwargs, match):
    with pytest.raises(InputError, match=match):
        spec(**kwargs)


def test_berkovich_faces_have_the_published_area_and_a_mirror_plane():
    text = input_text(spec())
    check_input(text)
    N = face_normals(text)
    assert N.shape == (3, 3)
    assert np.linalg.norm(N, axis=1) == pytest.approx(1.0, abs=1e-9)
    # each face makes 65.27 deg with the axis: its outward normal is that far below horizontal
    assert np.degrees(np.arcsin(-N[:, 2])) == pytest.approx(65.27, abs=1e-6)
    # x = 0 is a mirror plane: the set of normals is unchanged by x -> -x
    mirrored = N * [-1, 1, 1]
    assert sorted(map(tuple, mirrored.round(9))) == sorted(map(tuple, N.round(9)))
    # the cross-section 1 m above the apex: the triangle bounded by the three face lines
    # n_h . r = tan(theta) (n_h the horizontal unit normals); its area is A / h^2. The
    # published 24.494 uses 65.3 deg, the 24.5 of Oliver & Pharr 65.27 deg: 0.3 % apart
    n_h = N[:, :2] / np.linalg.norm(N[:, :2], axis=1)[:, None]
    c = -N[:, 2] / np.linalg.norm(N[:, :2], axis=1)        # tan(theta) per unit height
    corners = [np.linalg.solve(n_h[[i, j]], c[[i, j]]) for i, j in ((0, 1), (1, 2), (2, 0))]
    (x1, y1), (x2, y2), (x3, y3) = corners
    area = 0.5 * abs((x2 - x1) * (y3 - y1) - (x3 - x1) * (y2 - y1))
    assert area == pytest.approx(BERKOVICH_AREA, rel=3e-3)


def test_cube_corner_area():
    N = face_normals(input_text(spec("cube-corner", depth=4e-7)))
    theta = np.arcsin(-N[:, 2])
    # 3 sqrt(3) tan^2(theta) h^2, the equilateral triangle with inscribed radius h tan(theta)
    assert 3 * math.sqrt(3) * np.tan(theta)**2 == pytest.approx(CUBE_CORNER_AREA, rel=1e-3)


def test_pyramid_weights_load_and_reach():
    text = input_text(spec())
    K = si_to_lammps(K_FACTOR * AL.material.plane_strain_modulus, "pressure", "particle")
    kw = re.search(r"variable kw atom (\S+)\*\((.*)\)", text)
    assert float(kw.group(1)) == pytest.approx(K, rel=1e-9)
    assert kw.group(2) == "1-0.5*gmask(plane)"      # the symmetry-plane particles: half a cell
    assert "variable load equal -2*c_pyramid_z" in text      # the mirrored half doubles it
    # every particle the tip can reach at full depth is evaluated: the edge radius plus 2 dx
    reach = float(re.search(r"region near cylinder z 0 0 (\S+)", text).group(1))
    assert reach == pytest.approx(si_to_lammps(2 * 1.2e-7 * math.tan(math.radians(65.27)) + 2 * DX,
                                          "length", "particle"), rel=1e-9)
    full = input_text(spec(grid=Grid(DX, 1.2e-6, 1.2e-6, quarter=False)))
    assert "variable kw atom" in full and "gmask" not in full
    assert "variable load equal -1*c_pyramid_z" in full


def test_sphero_conical_sphere_and_frustum_are_tangent():
    R, theta = 2e-7, 70.3
    text = input_text(spec(f"sphero-conical:{R}:{theta}", grid=Grid(1e-7, 2e-6, 2e-6),
                           depth=3e-7))
    check_input(text)
    Ru = si_to_lammps(R, "length", "particle")
    sphere = re.search(r"fix ind_interior interior indent \S+ sphere 0 0 v_zc (\S+)", text)
    assert float(sphere.group(1)) == pytest.approx(Ru, rel=1e-9)
    cone = re.search(r"fix frustum_interior interior indent \S+ cone z 0 0 (\S+) (\S+) "
                     r"v_tangent v_tangent_top", text)
    r_lo, r_hi = float(cone.group(1)), float(cone.group(2))
    z_t = float(re.search(r"variable tangent equal -v_depth\+(\S+)", text).group(1))
    height = float(re.search(r"variable tangent_top equal v_tangent\+(\S+)", text).group(1))
    z_c = float(re.search(r"variable zc equal -v_depth\+(\S+)", text).group(1))
    assert z_c == pytest.approx(Ru, rel=1e-9)
    # the frustum's bottom circle lies on the sphere and its side has the cone's slope
    assert r_lo**2 + (z_c - z_t)**2 == pytest.approx(Ru**2, rel=1e-9)
    assert (r_hi - r_lo) / height == pytest.approx(math.tan(math.radians(theta)), rel=1e-9)
    # the side is tangent to the sphere: its distance from the centre is R
    dist = (r_lo + (z_c - z_t) * math.tan(math.radians(theta))) * math.cos(math.radians(theta))
    assert dist == pytest.approx(Ru, rel=1e-9)
    # quarter model: each geometry has its three weight groups and both enter the load
    assert text.count("frustum_") >= 6 and text.count("ind_") >= 6
    load = re.search(r"variable load equal 4\*\((.*)\)", text).group(1)
    assert len(load.split("+")) == 6


def test_contact_radius_of_each_tip():
    h = 1e-7
    tan = math.tan(math.radians(65.27))
    assert contact_radius(parse_tip("berkovich"), h) == pytest.approx(2 * h * tan)
    assert contact_radius(parse_tip("cone:70.3"), h) == pytest.approx(
        h * math.tan(math.radians(70.3)))
    tip = parse_tip("sphero-conical:200nm:70.3")
    h_a = tip.transition_depth
    # continuous at the tangent depth: the sphere's and the cone's radius meet there
    assert contact_radius(tip, h_a * (1 - 1e-9)) == pytest.approx(
        contact_radius(tip, h_a * (1 + 1e-9)), rel=1e-6)
    assert contact_radius(tip, h_a) == pytest.approx(2e-7 * math.cos(math.radians(70.3)))


def test_sneddon_closed_forms():
    E_star = 70e9 / (1 - 0.09)
    cone, berk = parse_tip("cone:70.3"), parse_tip("berkovich")
    # Sneddon's cone: P = (2/pi) E* tan(alpha) h^2; the pyramid adds King's 1.034
    assert sneddon_force(1e-7, cone, E_star) == pytest.approx(
        2 / math.pi * E_star * math.tan(math.radians(70.3)) * 1e-14, rel=1e-12)
    assert sneddon_force(1e-7, berk, E_star) / sneddon_force(1e-7, cone, E_star) == \
        pytest.approx(1.034, rel=1e-12)
    # the block: sqrt(P / C) = h + c P holds, and a deep block tends to the half-space
    h, H = np.array([0.05e-6, 0.1e-6, 0.2e-6]), 1.2e-6
    P = block_elastic_force(h, berk, 70e9, 0.3, H)
    C = float(sneddon_force(1.0, berk, E_star))
    c = 1.3 * 2.4 / (2 * math.pi * 70e9 * H)
    assert np.sqrt(P / C) == pytest.approx(h + c * P, rel=1e-10)
    assert np.all(P > sneddon_force(h, berk, E_star))
    assert block_elastic_force(h, berk, 70e9, 0.3, 1e3) == pytest.approx(
        sneddon_force(h, berk, E_star), rel=1e-6)


def test_sphero_conical_force_meets_hertz_and_sneddon_in_its_limits():
    E_star = 76.9e9
    tip = parse_tip("sphero-conical:500nm:70.3")
    # shallow, on the cap: Hertz with the tip radius. The cap's exact slope r/sqrt(R^2 - r^2)
    # differs from Hertz's parabola r/R by (a/R)^2/2, 1.5e-3 at a = sqrt(R h), h = 1e-3 R
    h = 1e-3 * tip.R
    assert sphero_conical_force(h, tip, E_star) == pytest.approx(
        float(hertz_force(h, tip.R, E_star)), rel=2e-3)
    # a rounding of 0.1 nm at 1 um depth: Sneddon's cone; the rounding itself moves the load
    # by at most 2 offset / h = 1.2e-5, the bound below leaves the rest to the quadrature
    sharp = parse_tip("sphero-conical:1e-10:70.3")
    assert sphero_conical_force(1e-6, sharp, E_star) == pytest.approx(
        float(sneddon_force(1e-6, parse_tip("cone:70.3"), E_star)), rel=5e-5)
    # between the two: stiffer than the cone through the same apex (the cap is blunter),
    # softer than the cone moved down by the offset R (1/sin(theta) - 1)
    hs = np.array([0.05e-6, 0.1e-6, 0.2e-6])
    P = sphero_conical_force(hs, tip, E_star)
    cone = parse_tip("cone:70.3")
    offset = tip.R * (1 / math.sin(math.radians(70.3)) - 1)
    assert np.all(P > sneddon_force(hs, cone, E_star))
    assert np.all(P < sneddon_force(hs + offset, cone, E_star))


def test_loading_only_ends_after_the_hold():
    loading = IndentLoading(1.2e-7, 60.0, hold_time=1e-9, unload=False)
    assert loading.times == pytest.approx((2e-9, 3e-9, 3e-9), rel=1e-12)
    text = input_text(ParticleIndentSpec(name="tip", method="tlsph", target=ParticleTarget(AL),
                                         tip="berkovich", loading=loading,
                                         grid=Grid(DX, 1.2e-6, 1.2e-6, quarter=False,
                                                   half=True)))
    assert "variable finished equal v_t>=3\n" in text       # ns: the end of the hold
    with pytest.raises(InputError, match="loading.unload"):
        IndentLoading(1.2e-7, 60.0, unload="no")


@pytest.mark.parametrize("tip", ["berkovich", "sphero-conical:500nm:70.3"])
def test_analysis_of_a_closed_form_loading(tip):
    # a loading-only history 3 % under the block's closed form, with lattice-like noise
    # whose mean is zero: both ratios come back as least-squares factors over 0.5-1 h_max
    sp = spec(tip)
    h = np.linspace(0.0, sp.loading.depth, 401)
    t = h / sp.loading.speed
    noise = 1 + 0.05 * np.sin(np.arange(h.size) * 2.1)
    block = block_elastic_force(h, sp.tip, 70e9, 0.3, sp.grid.depth)
    run = ParticleRun(spec=sp, run_dir=None, time=t, depth=h, load=0.97 * block * noise,
                      extra=np.zeros_like(h), snapshots=(), steps=0, wall_time=0.0)
    out = analyze_indent(run)
    # the noise's weighted mean over the 200 fitted points is below 1e-3
    assert out.block_ratio == pytest.approx(0.97, abs=2e-3)
    half_space = block_elastic_force(h, sp.tip, 70e9, 0.3, 1e6)       # H -> infinity
    sel = h >= 0.5 * h[-1]
    expected = np.sum(0.97 * block[sel] * noise[sel] * half_space[sel]) / np.sum(
        half_space[sel]**2)
    assert out.sneddon_ratio == pytest.approx(expected, rel=1e-5)
    assert out.sneddon_ratio > out.block_ratio          # the rigid base stiffens the block
    assert math.isnan(out.hertz_ratio) and math.isnan(out.residual_depth)
