"""Pipeline scenes: a scene whose layers may be calibrated from sources (MD or particle runs,
curve files) instead of stated, with the outputs it asks for. `parse_pipeline` checks every
key before any unit runs; `PipelineScene.completed` fills the calibrated materials in and
gives the `Scene` of `workflows.scene`. A sliding scene (a [slider] instead of an
[impactor], `workflows.slide_scene`) takes the same sources; `PipelineScene.slide_scene`
gives its `SlideScene`. See docs/pipeline.md and docs/scenes.md.
"""

from __future__ import annotations

import copy
import functools
from dataclasses import dataclass, replace
from pathlib import Path


from filmscale.continuum import (ElasticPlastic)
from filmscale.continuum.calibration.result import EXCLUDES
from filmscale.continuum.calibration.target import CONTACT_ZEROS, TIP_MATERIALS
from filmscale.continuum.indentation.oliver_pharr import check_curve_modulus
from filmscale.continuum.indentation.tips import parse_tip
from filmscale.continuum.materials import check_layer_count
from filmscale.core.checks import (THICKNESS_MAX,
                                   check_choice, check_keys,
                                   check_path, check_real)
from filmscale.core.errors import InputError
from filmscale.core.files import parse_toml, read_text

from filmscale.workflows.scene import (MATERIAL_KEYS, MapSpec, Scene, check_layer_headers,
                                       check_scene_data, material, read_impactor,
                                       read_map_spec, scene_from_data, si_quantities)
from filmscale.workflows.slide_scene import (SLIDE_OUTPUTS, SlideScene, check_slide_data,
                                             contact_friction, slide_scene_from_data)


OUTPUTS = ("maxima", "history", "map", "restitution", "residual_damage", "tangential")


@functools.lru_cache(maxsize=None)
def _md_spec(md: str, base: Path):
    from filmscale.md.spec import PRESETS, load_spec, preset
    return preset(md) if md in PRESETS else load_spec(base / md)


@functools.lru_cache(maxsize=None)
def _particle_spec(name: str, base: Path):
    from filmscale.md.particle_spec import PRESETS, load_spec, preset
    return preset(name, "indent") if name in PRESETS["indent"] else \
        load_spec(base / name, "indent")


SOURCE_KINDS = ("md", "particles", "curves")




@dataclass(frozen=True)
class CalibrationSource:
    """Where a layer's E and sigma_y come from: an MD indentation (preset or spec file), a
    particle-model indentation (preset or spec file), or curve files (measured), and what the
    curves were measured on: the tip's material (rigid for runs, diamond by default for curve
    files) and, for a film, its thickness and substrate (an MD run's film on its MD substrate
    and a particle model's film on its own substrate are known from the run; curve files
    state them)."""

    layer: int
    name: str
    kind: str                    #: one of SOURCE_KINDS
    source: tuple[str, ...]      #: the preset or spec file, or the curve files
    np: int = 1
    tip: str = ""                #: indenter of curve files that do not name one
    tolerance: float | None = None   #: of the cross-scale check; None: from the noise
    tip_material: str = "diamond"
    film_thickness: float | None = None     #: m, curve files on a stated substrate
    substrate: ElasticPlastic | None = None
    exclude: str = ""            #: range the cross-scale check leaves out ("pop-in")
    seeds: int = 1               #: MD ensemble members (one run unit each)
    #: "fit" or "fixed" (`calibrate`'s contact_zero); None: `calibrate`'s default (fit for a
    #: rigid tip, fixed for diamond). Particle sources default to "fixed".
    contact_zero: str | None = None
    #: "amorphous": the MD spec's top film is named by a melt-quench recipe (its block is
    #: made in the store before the run); "" for a spec as it stands
    structure: str = ""
    density: float | None = None     #: kg/m^3, the amorphous film's recipe at this density

    @property
    def label(self) -> str:
        """The source as results name it: ``md:quick``, ``curves:a.csv,b.h5``."""
        return f"{self.kind}:{','.join(self.source)}"

    def spec(self, base: Path):
        """The run's spec (None for curve files)."""
        if self.kind == "md":
            spec = _md_spec(self.source[0], Path(base).resolve())
            return amorphous_top(spec, self) if self.structure else spec
        if self.kind == "particles":
            return _particle_spec(self.source[0], Path(base).resolve())
        return None

    def member_specs(self, base: Path) -> list:
        """The run's spec for each ensemble member: the spec's own seed, then seeds derived
        from it (`md.indentation.derive_seeds`), one run unit each."""
        spec = self.spec(base)
        if self.seeds == 1:
            return [spec]
        from filmscale.md.indentation import derive_seeds
        master = spec.protocol.seed
        derived = derive_seeds(master, tuple(f"member{i}" for i in range(1, self.seeds)))
        members = [spec.with_protocol(seed=s) for s in derived.values()]
        if self.structure:      # each member's film from its own quench seed (its own block)
            members = [amorphous_top(m, self, quench_seed=i)
                       for i, m in enumerate(members, start=1)]
        return [spec] + members

    def films(self, spec, where: str = "calibrate") -> tuple:
        """The films of a run's spec, top first: the calibrated layer is the top one, on the
        run's substrate; more than one film is refused (its stack is not calibrated)."""
        films = spec.slab.films if self.kind == "md" else spec.target.films
        if len(films) > 1:
            raise InputError(f"{where}: the {self.kind} run {self.source[0]} has "
                             f"{len(films)} films; a calibration takes one film on its "
                             "substrate")
        return films

    def film(self, base: Path, record: dict | None = None):
        """(thickness, substrate) of the calibrated layer as a film, or (None, None) for a
        half-space: stated for curve files, the particle target's own, and for an MD run its
        top film on the substrate whose elastic constants its run unit computed from the
        potential (``record["film"]``)."""
        if self.kind == "curves":
            return self.film_thickness, self.substrate
        if self.kind == "particles":
            spec = self.spec(base)
            films = self.films(spec)
            return (films[0][0], spec.target.substrate.material) if films else (None, None)
        film = (record or {}).get("film")
        if not film:
            return None, None
        sub = film["substrate"]
        return film["thickness"], ElasticPlastic(sub["E"], sub["nu"], name=sub["name"])

    def curves(self, base: Path) -> list:
        """The curves of curve files, each with its indenter (``tip`` where unnamed)."""
        from filmscale.continuum.indentation.io import read_curves
        out = []
        for name in self.source:
            for key, c in read_curves(Path(base) / name).items():
                if not c.indenter:
                    if not self.tip:
                        raise InputError(f"target.layers[{self.layer}].calibrate: curve "
                                         f"{key!r} of {name} names no indenter; give tip "
                                         "(e.g. \"sphere:5um\" or \"berkovich\")")
                    c = replace(c, indenter=self.tip)
                out.append(check_curve_modulus(c))
        return out


def amorphous_top(spec, src: CalibrationSource, quench_seed: int = 0):
    """``spec`` with its top film's recipe at the source's ``density`` and its quench seed
    moved on by ``quench_seed``; InputError when the top film is not named by a recipe."""
    from filmscale.md.amorphous_film import AmorphousLayer
    films = spec.slab.films
    where = f"target.layers[{src.layer}].calibrate"
    if not films or not isinstance(films[0], AmorphousLayer) or films[0].recipe is None:
        raise InputError(f"{where}.structure = \"amorphous\": the top film of the MD spec "
                         f"{src.source[0]} must be amorphous and name its recipe "
                         "(structure = \"amorphous\", recipe = ...; docs/amorphous.md)")
    top = films[0]
    changes = {"seed": top.recipe.seed + quench_seed} if quench_seed else {}
    if src.density is not None:
        changes["density"] = src.density
    if not changes:
        return spec
    recipe = replace(top.recipe, **changes)
    slab = replace(spec.slab, films=(AmorphousLayer.named_by(recipe, top.thickness, top.gap),
                                     *films[1:]))
    return replace(spec, slab=slab, slab_built=None)


@dataclass(frozen=True)
class PipelineScene:
    """A parsed pipeline scene: the impact scene's data (layers to calibrate lack E and
    sigma_y until `completed`), the calibration sources and the outputs wanted."""

    data: dict
    text: str
    source: str
    base: Path
    calibrations: tuple[CalibrationSource, ...]
    outputs: frozenset
    tolerance: float
    friction: float
    angle: float

    @property
    def sliding(self) -> bool:
        """Whether this is a sliding scene (a [slider]; `slide_scene`), not an impact."""
        return "slider" in self.data

    @property
    def model_target(self) -> str:
        """``model.target`` (checked by `parse_pipeline`): "auto", "layered" or "substrate"."""
        model = self.data.get("model")
        return str(model.get("target", "auto")) if isinstance(model, dict) else "auto"

    def map_spec(self) -> MapSpec:
        """The scene's [map] axes (known before any calibration)."""
        impactor = read_impactor(self.data)
        return read_map_spec(self.data, impactor.mass, impactor)

    def completed(self, materials: dict[int, ElasticPlastic],
                  h_star: dict[int, float] | None = None) -> Scene:
        """The impact scene with each calibrated layer's E and sigma_y (and the Nix-Gao
        length h*, where calibrated) filled in."""
        return scene_from_data(filled_data(self.data, materials, h_star), self.text, self.source,
                               self.base)

    def slide_scene(self, materials: dict[int, ElasticPlastic]) -> SlideScene:
        """The sliding scene with each calibrated layer's E and sigma_y filled in (a Nix-Gao
        length is not: the sliding stresses are elastic, and a sliding scene takes none)."""
        return slide_scene_from_data(filled_data(self.data, materials, None), self.text,
                                     self.source, self.base)


def filled_data(data: dict, materials: dict[int, ElasticPlastic],
            h_star: dict[int, float] | None) -> dict:
    data = copy.deepcopy(data)
    for k, mat in materials.items():
        layer = data["target"]["layers"][k]
        layer.setdefault("E", mat.E)
        layer.setdefault("sigma_y", mat.sigma_y)
    for k, h in (h_star or {}).items():
        data["target"]["layers"][k].setdefault("h_star", h)
    return data


_SOURCE_KEYS = {"np", "tip", "tolerance", "exclude", "tip_material", "film_thickness",
                "substrate", "seeds", "contact_zero", "structure", "density"}


def _calibration_source(cal, where: str, layer: int, name: str) -> CalibrationSource:
    """One ``calibrate`` table, checked."""
    kinds = [key for key in SOURCE_KINDS if isinstance(cal, dict) and key in cal]
    if not isinstance(cal, dict) or set(cal) - set(SOURCE_KINDS) - _SOURCE_KEYS \
            or len(kinds) != 1:
        raise InputError(f"{where} takes exactly one of md (an MD preset or spec file), "
                         "particles (a particle-model preset or spec file) or curves (a "
                         f"list of curve files), and {', '.join(sorted(_SOURCE_KEYS))}; got "
                         f"{cal!r} (one layer takes several sources as "
                         "[[target.layers.calibrate]] tables)")
    kind = kinds[0]
    np_ = cal.get("np", 1)
    if isinstance(np_, bool) or not isinstance(np_, int) or not 1 <= np_ <= 4096:
        raise InputError(f"{where}.np = {np_!r} must be an integer in [1, 4096]")
    given = cal[kind]
    files = given if kind == "curves" else [given]
    if not isinstance(files, list) or not files or \
            not all(isinstance(f, str) for f in files):
        raise InputError(f"{where}.{kind} = {given!r} must be "
                         + ("a non-empty list of file names" if kind == "curves"
                            else "a preset name or a spec file name"))
    tip = cal.get("tip", "")
    if tip:
        parse_tip(tip)
    tol = None if "tolerance" not in cal else \
        check_real(f"{where}.tolerance", cal["tolerance"], low=1e-4, high=1.0)
    exclude = check_choice(f"{where}.exclude", cal.get("exclude", ""), EXCLUDES)
    tip_material = check_choice(f"{where}.tip_material",
                                cal.get("tip_material", "diamond" if kind == "curves"
                                        else "rigid"), TIP_MATERIALS)
    if kind != "curves" and tip_material != "rigid":
        raise InputError(f"{where}.tip_material = {tip_material!r}: the tips of MD and "
                         "particle runs are rigid")
    if ("film_thickness" in cal) != ("substrate" in cal):
        raise InputError(f"{where}: film_thickness and substrate go together (the film's "
                         "thickness and what it was measured on)")
    thickness = substrate = None
    if "film_thickness" in cal:
        if kind != "curves":
            raise InputError(f"{where}.film_thickness: an {kind} run knows its own film and "
                             "substrate; film_thickness and substrate are for curve files")
        thickness = check_real(f"{where}.film_thickness", cal["film_thickness"], low=0.0,
                               low_open=True, high=THICKNESS_MAX, unit="m")
        raw = check_keys(f"{where}.substrate", cal["substrate"], MATERIAL_KEYS)
        substrate = material(f"{where}.substrate", raw, require_yield="sigma_y" in raw)
    seeds = cal.get("seeds", 1)
    if isinstance(seeds, bool) or not isinstance(seeds, int) or not 1 <= seeds <= 64:
        raise InputError(f"{where}.seeds = {seeds!r} must be an integer in [1, 64]")
    if seeds > 1 and kind != "md":
        raise InputError(f"{where}.seeds: ensembles are of MD runs (thermal noise and the "
                         f"pop-in load vary with the seed); a {kind} source takes none")
    # a particle model's surface is where its contact law places it: a fitted zero took the
    # particle test's E from 70 to 95 GPa (the first particle layer's contact is not Hertzian)
    zero = cal.get("contact_zero", "fixed" if kind == "particles" else None)
    if zero is not None:
        check_choice(f"{where}.contact_zero", zero, CONTACT_ZEROS)
    structure, density = _amorphous_keys(cal, where, kind)
    return CalibrationSource(layer, name, kind, tuple(files), np_, str(tip), tol,
                             tip_material, thickness, substrate, exclude, seeds, zero,
                             structure, density)


def _amorphous_keys(cal: dict, where: str, kind: str) -> tuple[str, float | None]:
    """``structure`` ("amorphous": an MD source's film named by a recipe) and ``density``
    (kg/m^3, checked as a recipe's), checked."""
    structure = cal.get("structure", "")
    if structure:
        check_choice(f"{where}.structure", structure, ("amorphous",))
    if structure and kind != "md":
        raise InputError(f"{where}.structure: an amorphous film is quenched in MD; a {kind} "
                         "source takes none")
    if "density" not in cal:
        return structure, None
    if not structure:
        raise InputError(f"{where}.density is the density of an amorphous film's quench; give "
                         "structure = \"amorphous\" with it")
    from filmscale.md.amorphous import DENSITY_RANGE
    density = check_real(f"{where}.density", cal["density"], low=DENSITY_RANGE[0],
                         high=DENSITY_RANGE[1], unit="kg/m^3")
    return structure, density


def _outputs(data: dict, sliding: bool) -> tuple[list, float]:
    """[outputs] want and tolerance, checked: an impact scene's outputs (`OUTPUTS`), or a
    sliding scene's (`SLIDE_OUTPUTS`), which refuses the impact-only ones by name."""
    outputs = data.pop("outputs", {})
    if not isinstance(outputs, dict) or set(outputs) - {"want", "tolerance"}:
        raise InputError("[outputs] takes want (a list) and tolerance; got "
                         f"{sorted(outputs) if isinstance(outputs, dict) else outputs!r}")
    valid = SLIDE_OUTPUTS if sliding else OUTPUTS
    want = outputs.get("want", [valid[0]])
    if not isinstance(want, list) or not want:
        raise InputError(f"outputs.want must be a list from {', '.join(valid)}; got {want!r}")
    for i, w in enumerate(want):
        if sliding and w in OUTPUTS:
            raise InputError(f"outputs.want[{i}] = {w!r} is an impact output; a sliding scene "
                             f"([slider]) computes {', '.join(SLIDE_OUTPUTS)} (the choices of "
                             "outputs.want)")
        check_choice(f"outputs.want[{i}]", w, valid)
    # 0: keep everything the rules can keep (rule 3 keeps the films whenever they change
    # the maxima at all; docs/pipeline.md, "The plan")
    tolerance = check_real("outputs.tolerance", outputs.get("tolerance", 0.05), low=0.0,
                           high=0.5)
    return want, tolerance


def _motion(data: dict, sliding: bool, base: Path) -> tuple[float, float]:
    """(friction, angle in degrees) of the scene: [contact] friction (a sliding scene's may
    be a scratch record's, `slide_scene.contact_friction`); an impactor's angle (a slider
    slides along its surface: 0)."""
    if sliding:
        return contact_friction(data, base)[0], 0.0
    contact = data.get("contact") if isinstance(data.get("contact"), dict) else {}
    imp = data.get("impactor", {})
    if "friction" in imp:
        raise InputError("impactor.friction: the friction coefficient is [contact] friction, "
                         "as in `filmscale impact` (docs/scenes.md)")
    friction = check_real("contact.friction", contact.get("friction", 0.0), low=0.0, high=10.0)
    angle = check_real("impactor.angle", imp.pop("angle", 0.0), low=0.0, high=90.0,
                       high_open=True, unit="degrees")
    return friction, angle


def parse_pipeline(text: str, source: str = "<scene>", base: Path | None = None
                   ) -> PipelineScene:
    """Validate a pipeline scene, an impact scene or a sliding one (a [slider]); an MD spec
    is loaded (and checked) here, before any run."""
    base = Path(".") if base is None else base
    check_layer_headers(text)
    data = si_quantities(parse_toml(text, "scene", source))
    sliding = "slider" in data
    want, tolerance = _outputs(data, sliding)
    friction, angle = _motion(data, sliding, base)
    sources = []
    layers = data.get("target", {}).get("layers", [])
    if isinstance(layers, list):
        check_layer_count("target.layers", len(layers))
    for k, layer in enumerate(layers if isinstance(layers, list) else []):
        if not isinstance(layer, dict) or "calibrate" not in layer:
            continue
        cal = layer.pop("calibrate")
        tables = cal if isinstance(cal, list) and cal else [cal]
        given = "E" in layer and "sigma_y" in layer     # given properties win (rule 1)
        for j, table in enumerate(tables):
            where = f"target.layers[{k}].calibrate" + (f"[{j}]" if isinstance(cal, list)
                                                       else "")
            src = _calibration_source(table, where, k, str(layer.get("name", f"layer {k}")))
            if given:
                continue
            if src.kind == "curves":
                src.curves(base)    # readable, each with an indenter, before any work
            else:
                src.films(src.spec(base), where)    # the spec's own checks, before any work
            sources.append(src)
    pipeline = PipelineScene(data, text, source, base, tuple(sources), frozenset(want),
                             tolerance, friction, angle)
    # every other key checked now, the calibrated layers' E and sigma_y excepted
    pending = {s.layer for s in sources}
    if sliding:
        check_slide_data(data, pending, base)
    else:
        check_scene_data(data, pending)
    return pipeline


def load_pipeline(path) -> PipelineScene:
    path = check_path("path", path)
    return parse_pipeline(read_text(path, "scene"), str(path), path.parent)


def layer_sources(pipeline: PipelineScene) -> dict[int, list[CalibrationSource]]:
    """The calibration sources of each layer to calibrate, in scene order."""
    by_layer: dict[int, list[CalibrationSource]] = {}
    for src in pipeline.calibrations:
        by_layer.setdefault(src.layer, []).append(src)
    return by_layer
