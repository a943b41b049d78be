"""``filmscale calibrate``: a layer's E, sigma_y (and n) from curve files, through the same
function the scene pipeline calls (`filmscale.continuum.calibration.route.calibrate`).

What a run record (``filmscale md indent``, ``filmscale particles indent``) already holds is
taken from it (`curve_inputs`): a simulated curve's rigid tip, and the film on a substrate of
the run (its thickness from the record's spec; an MD substrate's E and nu from the potential's
elastic constants, as the scene pipeline's run unit computes them). ``--strict`` makes the
exit status say whether the calibration is one to trust (`strict_reasons`)."""

from __future__ import annotations

import argparse
import json
import math
import sys
from dataclasses import asdict, dataclass, replace
from pathlib import Path

import numpy as np

from filmscale.core.errors import EngineError, InputError
from filmscale.core.files import check_regular_file
from filmscale.core.jsonable import dumps

from .quantity_args import add_quantity_argument

#: the start of a simulated curve's ``meta["source"]`` (MD and particle-model runs): its
#: tip is rigid
SIMULATED_SOURCE = "filmscale.md "
PARTICLE_SOURCE = "filmscale.md particle model"


def substrate_arg(text: str):
    """E,nu[,sigma_y] in Pa or with units ("90 GPa,0.25,2 GPa"): the substrate under a film."""
    from filmscale.continuum.materials import ElasticPlastic
    from filmscale.core.quantities import to_si
    parts = text.split(",")
    try:
        values = [float(to_si(f"--substrate {name}", v, unit))
                  for v, name, unit in zip(parts, ("E", "nu", "sigma_y"), ("Pa", "", "Pa"))]
    except (InputError, ValueError) as err:
        raise argparse.ArgumentTypeError(f"expected E,nu[,sigma_y] (Pa or with units), got "
                                         f"{text!r}: {err}") from None
    if len(parts) not in (2, 3):
        raise argparse.ArgumentTypeError(f"expected E,nu[,sigma_y] (Pa), got {text!r}")
    try:
        return ElasticPlastic(*values, name="substrate")
    except InputError as err:
        raise argparse.ArgumentTypeError(f"--substrate: {err}") from None


#: the layer's Poisson ratio assumed when neither --nu nor a run record gives one
DEFAULT_NU = 0.3


# ---- what a run record holds ---------------------------------------------------------------

@dataclass(frozen=True)
class RecordFilm:
    """The calibrated layer as a run record states it: its kind ("md" or "particles"), the
    top film's thickness (None: the run indented a half-space) and how to get its substrate
    (``substrate()``: an MD run's from the potential, which takes LAMMPS; computed only when
    no ``--substrate`` is given)."""

    path: str
    kind: str
    thickness: float | None
    substrate_key: str            #: tells substrates apart without computing them
    substrate_how: str            #: where the substrate's values come from
    spec: object = None           #: the parsed particle spec, or (potential record, crystal)
    nu: float | None = None       #: the film's own Hill nu (an MD record's elastic constants)

    def substrate(self):
        from filmscale.continuum.materials import ElasticPlastic
        if self.thickness is None:
            return None
        if self.kind == "particles":       # the particle target's own (`CalibrationSource.film`)
            return self.spec.target.substrate.material
        potential, crystal = _record_potential(self.path, self.spec[0]), self.spec[1]
        # the scene pipeline's MD run unit (`units.run_md`): the potential's own 0 K elastic
        # constants of the substrate crystal, Voigt-Reuss-Hill averaged
        from filmscale.md.elastic import elastic_constants
        try:
            average = elastic_constants(potential, crystal).average
        except EngineError as err:
            raise EngineError(f"{self.path}: the substrate's E and nu come from potential "
                              f"{potential.name}'s elastic constants of {crystal.element}, "
                              f"computed with LAMMPS: {err} (or give --substrate "
                              "E,nu[,sigma_y])") from None
        return ElasticPlastic(average.E, average.nu, name=crystal.element)


def _record_potential(path: str, d: dict):
    """The potential a record's spec names: the registry's entry of that name when its file
    has the record's checksum, else the record's own file where it still is."""
    from filmscale.potentials.registry import PotentialError, get_potential, potential_from_mapping
    name, sha = d.get("name"), d.get("sha256")
    try:
        pot = get_potential(name)
        if not sha or pot.sha256 == sha:
            return pot
    except PotentialError:
        pass
    if d.get("path") and Path(d["path"]).is_file():
        keys = ("name", "elements", "pair_style", "pair_coeff", "citation", "sha256", "doi",
                "units")
        try:
            return potential_from_mapping({"file": d["path"], **{k: d[k] for k in keys
                                                                  if d.get(k) is not None}})
        except PotentialError:
            pass
    raise InputError(f"{path}: the run's potential {name} (sha256 {sha}) is not in the "
                     "registry here nor at its recorded path; give --substrate E,nu[,sigma_y] "
                     "for the substrate under the film")


def _md_film(path: str, spec: dict) -> RecordFilm:
    from filmscale.md.structures import Crystal
    slab = spec["slab"]
    films = slab.get("films") or []
    if len(films) > 1:                   # as `CalibrationSource.films`
        raise InputError(f"{path}: the MD run has {len(films)} films; a calibration takes "
                         "one film on its substrate")
    if not films:
        return RecordFilm(path, "md", None, "", "")
    sub = Crystal(**slab["substrate"]["crystal"])
    pot = spec["potential"]
    how = (f"{sub.element} ({sub.structure}) with potential {pot.get('name')}: Voigt-Reuss-Hill "
           "average of its 0 K elastic constants")
    return RecordFilm(path, "md", float(films[0]["thickness"]),
                      json.dumps([pot.get("sha256") or pot.get("name"), asdict(sub)]), how,
                      (pot, sub))


def _particle_film(path: str, spec: dict) -> RecordFilm:
    from filmscale.md.particle_spec import spec_from_mapping
    kind = spec.pop("kind", "indent")
    if kind == "impact":            # `ParticleImpactSpec.to_dict` keeps its section flat
        section = {k: spec.pop(k) for k in ("mass", "velocity", "duration", "frames")
                   if k in spec}
        spec["impact"] = {k: v for k, v in section.items() if v is not None}
    parsed = spec_from_mapping(spec, kind)
    films = parsed.target.films
    if len(films) > 1:
        raise InputError(f"{path}: the particle run has {len(films)} films; a calibration "
                         "takes one film on its substrate")
    if not films:
        return RecordFilm(path, "particles", None, "", "", parsed)
    sub = parsed.target.substrate.material
    return RecordFilm(path, "particles", float(films[0][0]), json.dumps(asdict(sub)),
                      "the particle model's substrate", parsed)


def record_film(path) -> RecordFilm | None:
    """What the run record at ``path`` says of the film (None: not a run record)."""
    import h5py

    from filmscale.continuum.indentation.io import HDF5_SUFFIXES
    if Path(path).suffix.lower() not in HDF5_SUFFIXES:
        return None
    try:
        check_regular_file(path, "run record")  # h5py would block on a named pipe
    except InputError:
        return None                  # read_curves says what is wrong with the file
    try:
        with h5py.File(path, "r") as f:
            fmt = f.attrs.get("format", "")
            if not (isinstance(fmt, str) and fmt.startswith("filmscale.md_")):
                return None
            text = f["inputs/spec.json"][()] if "inputs/spec.json" in f else None
            average = f["elastic"].attrs.get("average") if "elastic" in f else None
    except OSError:
        return None                  # read_curves says what is wrong with the file
    from filmscale.md.particle_run import RECORD_FORMAT as PARTICLES
    from filmscale.md.record import RECORD_FORMAT as MD
    if fmt not in (MD, PARTICLES) or text is None:
        return None
    try:
        spec = json.loads(text.decode() if isinstance(text, bytes) else text)
        film = (_md_film if fmt == MD else _particle_film)(str(path), spec)
        return film if average is None else replace(film, nu=float(json.loads(average)["nu"]))
    except (KeyError, TypeError, ValueError) as err:     # InputError is a ValueError
        raise InputError(f"{path}: the run's spec in the record cannot be read: "
                         f"{err}") from None


@dataclass(frozen=True)
class CurveInputs:
    """What the curves were measured on, and where each value came from ("record",
    "option" or "default")."""

    tip_material: str
    tip_material_from: str
    thickness: float | None
    substrate: object             #: ElasticPlastic or None
    thickness_from: str = "default"
    substrate_from: str = "default"
    substrate_how: str = ""       #: how a record's substrate was obtained
    contact_zero: str | None = None
    contact_zero_from: str = "default"
    notes: tuple[str, ...] = ()
    nu: float = DEFAULT_NU        #: the layer's Poisson ratio (`layer_nu`)
    nu_from: str = "default"

    @property
    def film_from(self) -> str:
        """Where the film (thickness and substrate) came from: "record", "option",
        "record and option" (one of each) or "default" (a half-space, nothing said)."""
        if self.thickness_from == self.substrate_from:
            return self.thickness_from
        return "record and option"

    def to_dict(self) -> dict:
        s = self.substrate
        return {"tip_material": self.tip_material, "tip_material_from": self.tip_material_from,
                "film_thickness": self.thickness,
                "substrate": None if s is None else {"E": s.E, "nu": s.nu, "sigma_y": s.sigma_y,
                                                     "name": s.name},
                "from": self.film_from, "film_thickness_from": self.thickness_from,
                "substrate_from": self.substrate_from, "substrate_how": self.substrate_how,
                "contact_zero": self.contact_zero, "contact_zero_from": self.contact_zero_from,
                "nu": self.nu, "nu_from": self.nu_from}

    def lines(self) -> list[str]:
        """The inputs taken from run records, for the text output."""
        from filmscale.core.quantities import eng
        out = []
        if self.tip_material_from == "record":
            out.append(f"tip material: {self.tip_material} (from the record)")
        if "record" in self.film_from:
            if self.thickness is None:
                out.append("target: a half-space (from the record)")
            else:
                s = self.substrate
                where = {"record": "from the record", "option": "as given"}
                out.append(
                    f"film: {eng(self.thickness, 'm')} ({where[self.thickness_from]}) on "
                    f"{s.name or 'the substrate'} (E {eng(s.E, 'Pa')}, nu {s.nu:.3g}"
                    + (f", sigma_y {eng(s.sigma_y, 'Pa')}" if math.isfinite(s.sigma_y) else "")
                    + f"; {where[self.substrate_from]}"
                    + (f": {self.substrate_how}" if self.substrate_how else "") + ")")
        if self.contact_zero_from == "record":
            out.append(f"contact zero: {self.contact_zero} (a particle model's surface, as "
                       "the scene pipeline takes it)")
        return out


def _source(curve) -> str:
    """What made a curve (``meta["source"]``; "" for a measured curve that says nothing)."""
    return str(curve.meta.get("source", ""))


def curve_inputs(files: list[tuple[str, list]], tip_material: str | None,
                 thickness: float | None, substrate, contact_zero: str | None = None,
                 nu: float | None = None) -> CurveInputs:
    """The tip material, film thickness, substrate and contact zero of a calibration of the
    curves of ``files`` ((path, curves) pairs): the options where given, else what run records
    hold (a simulation's tip is rigid; a record's film and substrate; a particle model's
    contact zero is held fixed, as in the scene pipeline), else today's defaults for measured
    curves (diamond, a half-space)."""
    curves = [c for _, cs in files for c in cs]
    records = {path: record_film(path) for path, _ in files}
    tip, tip_from = _tip_material(curves, tip_material)
    zero, zero_from = _contact_zero(curves, contact_zero)
    if any(r is not None for r in records.values()):
        film = _film_of_records(files, records, thickness, substrate)
    else:
        film = _film_of_measured(files, thickness, substrate)
    nu, nu_from = layer_nu(nu, list(records.values()))
    return CurveInputs(tip, tip_from, contact_zero=zero, contact_zero_from=zero_from, nu=nu,
                       nu_from=nu_from, **film)


def layer_nu(nu: float | None, records: list) -> tuple[float, str]:
    """(nu, where from): the option; else the mean Hill nu of the film's own elastic constants
    that every file's MD record holds (the potential's crystal, or an amorphous film's block:
    0.135 for the quick a-C block, whose E an assumed 0.3 lowered by 10 %); else
    `DEFAULT_NU`."""
    if nu is not None:
        return nu, "option"
    found = [r.nu for r in records if r is not None and r.nu is not None]
    if records and len(found) == len(records):
        return float(sum(found) / len(found)), "record"
    return DEFAULT_NU, "default"


def _tip_material(curves, tip_material: str | None) -> tuple[str, str]:
    """(tip material, where from): the option, else rigid for simulated curves, else diamond;
    InputError for simulated and measured curves together."""
    simulated = [_source(c).startswith(SIMULATED_SOURCE) for c in curves]
    if tip_material is not None:
        return tip_material, "option"
    if curves and all(simulated):
        return "rigid", "record"
    if any(simulated):
        raise InputError("the curves mix simulated runs (a rigid tip) and measured curves "
                         "(a diamond tip by default): give --tip-material, or calibrate them "
                         "apart")
    return "diamond", "default"


def _contact_zero(curves, contact_zero: str | None) -> tuple[str | None, str]:
    """(contact zero, where from): the option, else fixed for particle-model curves (as the
    scene's particle sources), else None: `calibrate`'s default (fit for a rigid sphere, else
    fixed)."""
    if contact_zero is not None:
        return contact_zero, "option"
    if curves and all(_source(c).startswith(PARTICLE_SOURCE) for c in curves):
        return "fixed", "record"
    return None, "default"


def _film_of_measured(files, thickness, substrate) -> dict:
    """The film of curves without a run record (`CurveInputs` fields): the options' film on
    its substrate, or a half-space; a note for each file of simulated curves without one."""
    notes = tuple(f"{path} holds simulated curves but no run record: a half-space unless "
                  "--film-thickness and --substrate say otherwise"
                  for path, cs in files
                  if any(_source(c).startswith(SIMULATED_SOURCE) for c in cs))
    if (thickness is None) != (substrate is None):
        raise InputError("--film-thickness and --substrate go together (a film on a "
                         "substrate), or leave both out (a half-space)")
    given = "option" if thickness is not None else "default"
    return dict(thickness=thickness, substrate=substrate, thickness_from=given,
                substrate_from=given, notes=notes)


def _film_of_records(files, records: dict, thickness, substrate) -> dict:
    """The film of curves with run records (`CurveInputs` fields): each of the film's
    thickness and substrate from the option, else from the records, which must agree."""
    held = [r for r in records.values() if r is not None]
    films = {r.path: r for r in held if r.thickness is not None}
    if not films:                           # every record: a half-space
        if (thickness is None) != (substrate is None):
            raise InputError("--film-thickness and --substrate go together: the record(s) "
                             "hold a half-space")
        given = "option" if thickness is not None else "record"
        return dict(thickness=thickness, substrate=substrate, thickness_from=given,
                    substrate_from=given)
    if thickness is None or substrate is None:
        _check_one_film(files, records, held, films)
    film = dict(thickness=thickness, substrate=substrate, thickness_from="option",
                substrate_from="option", substrate_how="")
    if thickness is None:
        film.update(thickness=_record_thickness(films), thickness_from="record")
    if substrate is None:
        first = _record_substrate(films)
        film.update(substrate=first.substrate(), substrate_from="record",
                    substrate_how=first.substrate_how)
    return film


def _check_one_film(files, records: dict, held: list, films: dict) -> None:
    """Where an option does not give the film whole, every file must hold a record of a film
    on a substrate: no file without a record, no record of a half-space."""
    if len(held) < len(files):
        others = ", ".join(path for path, r in records.items() if r is None)
        raise InputError(f"{', '.join(films)} hold(s) a film on a substrate but {others} "
                         "hold(s) no run record: give --film-thickness and --substrate")
    if len(films) < len(held):
        raise InputError(f"the records mix half-spaces and films ({', '.join(films)}): "
                         "calibrate them apart, or give --film-thickness and --substrate")


def _record_thickness(films: dict) -> float:
    """The film thickness the records hold, the same in each."""
    values = {r.thickness for r in films.values()}
    if len(values) > 1:
        raise InputError(f"the records hold films of different thicknesses "
                         f"({', '.join(f'{t:g} m' for t in sorted(values))}): calibrate "
                         "them apart, or give --film-thickness")
    return values.pop()


def _record_substrate(films: dict) -> RecordFilm:
    """The record whose substrate is the film's: the records' substrates are the same."""
    keys = {r.substrate_key for r in films.values()}
    if len(keys) > 1:
        raise InputError("the records hold films on different substrates: calibrate "
                         "them apart, or give --substrate")
    return next(iter(films.values()))


# ---- what --strict judges ------------------------------------------------------------------

def depth_law(cal) -> tuple[bool, bool, str]:
    """(tried, identified, reason) of the calibration's depth law of sigma_y (Nix-Gao h*):
    tried when it holds an h* or says a size-effect fit gave none; the reason says why h* is
    not identified, or why no depth law was tried."""
    if cal.h_star is not None:
        return True, bool(cal.h_star.identified), cal.h_star.reason
    for w in cal.warnings:
        if w.startswith("no size effect"):
            return True, False, w.removeprefix("no size effect: ")
    if cal.route == "sphere":
        return False, False, "a sphere calibration fits no depth law"
    if cal.route == "sharp":
        depths = {round(float(np.max(h)), 12) for h, _, _ in cal.fitted_curves}
        k = len(depths)
        if k:
            return False, False, (f"{'one depth' if k == 1 else f'{k} depths'}: a depth law "
                                  "needs sharp curves at three or more depths")
        return False, False, "a depth law needs sharp curves at three or more depths"
    return False, False, "no depth law was fitted"


def requested_parameters(cal) -> list[tuple[str, object]]:
    """The parameters a calibration is asked for: E and sigma_y; n where a sharp tip gives it
    (a sharp route, or a joint one with a sharp source); h* where a depth law was tried."""
    out = [("E", cal.E), ("sigma_y", cal.sigma_y)]
    if cal.route == "sharp" or any(c.get("route") == "sharp" for c in cal.components):
        out.append(("n", cal.n))
    tried, identified, reason = depth_law(cal)
    if tried:
        from filmscale.continuum.calibration.result import Parameter
        out.append(("h_star", cal.h_star if cal.h_star is not None else
                    Parameter(math.nan, math.nan, "m", False, reason)))
    return out


def strict_reasons(cal, checks) -> list[str]:
    """Why a calibration is not one to trust: each failed cross-scale check and each
    requested parameter (`requested_parameters`) the data do not identify; empty: none."""
    out = []
    for check in checks:
        if not check.passed:
            of = f" of {check.source}" if check.source else ""
            out.append(f"cross-scale check{of} failed (rms {check.rms:.1%} > tolerance "
                       f"{check.tolerance:.1%})" + (f": {check.lacks}" if check.lacks else ""))
    for name, p in requested_parameters(cal):
        if not p.identified:
            out.append(f"{name} not identified: {p.reason or 'no reason given'}")
    return out


def _parameter_keys(cal) -> dict:
    """E, sigma_y, n and h* flat: the value, std, identified and reason of each (n's value
    and std null when not identified; h*'s identified and reason those of `depth_law`)."""
    tried, h_identified, h_reason = depth_law(cal)
    return {
        "E": cal.E.value, "E_std": cal.E.std, "E_identified": cal.E.identified,
        "E_reason": cal.E.reason,
        "sigma_y": cal.sigma_y.value, "sigma_y_std": cal.sigma_y.std,
        "sigma_y_identified": cal.sigma_y.identified, "sigma_y_reason": cal.sigma_y.reason,
        "n": cal.n.value if cal.n.identified else None,
        "n_std": cal.n.std if cal.n.identified else None,
        "n_identified": cal.n.identified, "n_reason": cal.n.reason,
        "h_star": None if cal.h_star is None else cal.h_star.value,
        "h_star_std": None if cal.h_star is None else cal.h_star.std,
        "h_star_identified": bool(tried and h_identified),
        "h_star_reason": "" if tried and h_identified else h_reason}


def _check_keys(check) -> dict:
    """The cross-scale check: whole under "check", its verdict and numbers at the top."""
    return {"cross_check_rms": check.rms, "cross_check_tolerance": check.tolerance,
            "passed": check.passed, "cross_check_noise": check.noise,
            "cross_check_excluded": check.excluded, "cross_check_lacks": check.lacks,
            "check": check.to_dict()}


def _json(cal, check, inputs: CurveInputs) -> dict:
    """``calibrate --json``: the calibration's own fields (`Calibration.to_dict`; among them
    the pop-in law's third parameter, "pop_in": load (N), depth (m), shear stress 0.31 p0
    (Pa) with their scatter over the curves, null without a pop-in), its parameters flat
    (`_parameter_keys`; each parameter whole under "calibration"), and what the command
    adds: the cross-scale check (`_check_keys`) and the inputs taken from run records."""
    d = cal.to_dict()
    return {**d, **_parameter_keys(cal), **_check_keys(check), "inputs": inputs.to_dict(),
            "calibration": d}


def _one_protocol_runs(curves, inputs) -> bool:
    """Several run records sampled alike (seeds of one spec): their seed-to-seed scatter,
    which one joint fit's covariance does not hold, belongs in the calibration's stds."""
    from filmscale.continuum.calibration.ensemble import sampled_alike
    return len(curves) > 1 and inputs.tip_material_from == "record" and sampled_alike(curves)


def cmd_calibrate(args) -> int:
    from filmscale.continuum.calibration.route import calibrate
    from filmscale.continuum.indentation.io import read_curves
    files = [(path, list(read_curves(path).values())) for path in args.curves]
    inputs = curve_inputs(files, args.tip_material, args.film_thickness, args.substrate,
                          args.contact_zero, args.nu)
    if inputs.tip_material_from == "record":
        print("filmscale: tip material: rigid (from the record)", file=sys.stderr)
    for note in inputs.notes:
        print(f"filmscale: note: {note}", file=sys.stderr)
    curves = [c for _, cs in files for c in cs]
    if inputs.nu_from == "record":
        print(f"filmscale: nu {inputs.nu:.3g} (from the record: the film's own elastic "
              "constants, Voigt-Reuss-Hill)", file=sys.stderr)
    how = calibrate
    if _one_protocol_runs(curves, inputs):
        from filmscale.continuum.calibration.ensemble import calibrate_ensemble
        how = calibrate_ensemble
        print(f"filmscale: an ensemble of {len(curves)} runs of one protocol: each std the "
              "larger of the joint fit's and the runs' standard error", file=sys.stderr)
    cal = how(curves, nu=inputs.nu, tip=args.tip, tip_material=inputs.tip_material,
              thickness=inputs.thickness, substrate=inputs.substrate, law=args.law,
              layer=args.layer, contact_zero=inputs.contact_zero)
    check = cal.cross_check(args.tolerance, exclude=args.exclude)
    if args.json:
        print(dumps({**_json(cal, check, inputs), "nu_from": inputs.nu_from}))
    else:
        print(cal.summary())
        print(f"  {check.text()}")
        for line in inputs.lines():
            print(f"  {line}")
    for warning in cal.warnings:
        print(f"filmscale: warning: {warning}", file=sys.stderr)
    if args.strict:
        reasons = strict_reasons(cal, [check])
        for reason in reasons:
            print(f"filmscale: strict: {reason}", file=sys.stderr)
        return 1 if reasons else 0
    return 0


def add_strict_argument(p, what: str) -> None:
    p.add_argument("--strict", action="store_true",
                   help=f"exit with status 1 when {what}: a cross-scale check failed or a "
                        "requested parameter (E, sigma_y; n for sharp tips; h* where a depth "
                        "law was tried) is not identified; one line on stderr per reason")


def add_arguments(sub) -> None:
    """``calibrate``, on the top-level sub-parsers."""
    from filmscale.continuum.calibration.result import EXCLUDES, NOISE_FACTOR
    from filmscale.continuum.calibration.target import CONTACT_ZEROS, TIP_MATERIALS
    from filmscale.continuum.contact.laws import FIT_LAW, LAW_NAMES
    p = sub.add_parser(
        "calibrate", help="E, sigma_y (and n) of a layer from curve files",
        description="Calibrate a layer from load-displacement curves: spherical tips through "
                    "the contact law (on a half-space, or as a film on a stated substrate), a "
                    "sharp tip through Dao's reverse analysis. Prints E, sigma_y and n with "
                    "their standard deviations and the cross-scale check of the calibrated "
                    "forward model against the curves. A run record (filmscale md indent, "
                    "filmscale particles indent) gives its rigid tip and its film on a "
                    "substrate; the options override it.")
    p.add_argument("curves", nargs="+", help="curve files (text tables or HDF5)")
    p.add_argument("--tip", help="the tip of every curve, e.g. sphere:5um or berkovich "
                                 "(default: each curve's own)")
    p.add_argument("--tip-material", choices=TIP_MATERIALS, default=None,
                   help="rigid or diamond (default: rigid for MD and particle records, "
                        "diamond for measured curves)")
    add_quantity_argument(p, "--film-thickness", "m", metavar="T",
                          help="the layer is a film of thickness T (m, or with units: 1 um) "
                               "on --substrate (default: a run record's film, else none)")
    p.add_argument("--substrate", type=substrate_arg, metavar="E,nu[,sigma_y]",
                   help="the substrate under the film, Pa or with units: 90GPa,0.25,2GPa "
                        "(without sigma_y it takes the film's; default: a run record's, an "
                        "MD substrate's E and nu from the potential's elastic constants)")
    p.add_argument("--law", choices=LAW_NAMES, default=FIT_LAW,
                   help=f"sphere contact law (default {FIT_LAW}: continuous, so that a fit "
                        "can follow it)")
    p.add_argument("--contact-zero", choices=CONTACT_ZEROS,
                   help="sphere tips: fit the depth zero with E, or hold it fixed at the "
                        "curves' h = 0 (default: fit for a rigid tip, fixed for diamond and "
                        "for particle-model records)")
    p.add_argument("--nu", type=float,
                   help="the layer's Poisson ratio, assumed (default: an MD record's own, "
                        f"from its film's elastic constants, else {DEFAULT_NU})")
    p.add_argument("--layer", default="layer", help="the layer's name in the output")
    p.add_argument("--tolerance", type=float,
                   help="cross-scale check: largest rms misfit over the largest load "
                        f"(default {NOISE_FACTOR:g} x the curves' own load noise)")
    p.add_argument("--exclude", choices=[e for e in EXCLUDES if e], default="",
                   help="leave out of the check the first pop-in's burst (from its peak to "
                        "the bottom of its drop: what the pop-in law does not model) or the "
                        "whole pop-in range (the loading up to that bottom)")
    add_strict_argument(p, "the calibration is not one to trust")
    p.add_argument("--json", action="store_true", help="print one JSON object (SI)")
    p.set_defaults(func=cmd_calibrate)
