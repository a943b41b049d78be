"""Sliding scenes (TOML): a slider's protrusion held at a normal load and sliding with friction
on a target stack (`filmscale slide`, `slide-map`; docs/sliding.md).

A sliding scene holds [slider] (shape, radius, length of a cylinder, normal_load, optional E
and nu of an elastic slider), [target] as an impact scene's and [contact] friction, stated or
measured (``friction_from``: a scratch record of `filmscale md scratch`). Every key is checked
before any work starts, with the messages of the impact scenes (docs/scenes.md).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from filmscale.continuum.contact.slider import Slider
from filmscale.continuum.materials import LayerStack
from filmscale.core.checks import check_keys, check_path, required
from filmscale.core.errors import InputError
from filmscale.core.files import parse_toml, read_text
from filmscale.core.keys import Key, read_keys
from filmscale.core.quantities import to_si

from .scene import check_layer_headers, material, read_stack
from .scene_keys import key_names, quantity_units, section_keys

#: [contact] of a sliding scene: the friction, stated or measured by a scratch
FRICTION = Key("friction", "1", 0.0, 0.0, 10.0, section="contact",
               doc="Coulomb coefficient mu of the sliding contact (q = mu p)")
FRICTION_FROM = Key("friction_from", section="contact", valid="path",
                    doc="a scratch record (the scratch.h5 of `filmscale md scratch` or the "
                    "particle_scratch.h5 of `filmscale particles scratch`), relative to the "
                    "scene: its friction over the steady stroke is the contact's")
#: the top-level tables of a sliding scene
SECTIONS = {"title", "description", "slider", "target", "contact"}
#: what a sliding scene of the pipeline (`filmscale run`) computes: its [outputs] want
SLIDE_OUTPUTS = ("stresses",)


@dataclass(frozen=True)
class SlideScene:
    """A validated sliding scene; ``text`` is the TOML it came from (provenance)."""

    slider: Slider
    stack: LayerStack
    normal_load: float      #: N
    friction: float         #: Coulomb coefficient
    title: str = ""
    text: str = ""
    source: str = ""
    #: where a measured friction came from: {record, mean, std, points}; None when stated
    friction_source: dict | None = field(default=None, compare=False)


def _in_si(where: str, table: dict) -> dict:
    table = dict(table)
    for key, unit in quantity_units(where).items():
        if key in table:
            table[key] = to_si(f"{where}.{key}", table[key], unit, text_numbers=False)
    return table


def read_slider(data: dict) -> tuple[Slider, float]:
    """The [slider] section: the slider and its normal load (N)."""
    raw = check_keys("slider", required("scene", data, "slider"), key_names("slider"))
    raw = _in_si("slider", raw)
    shape = section_keys("slider")[0].read("slider", raw)
    own = {k.name for k in section_keys("slider", shape)}
    for name in raw:
        if name not in own:
            raise InputError(f"slider.{name} applies to other slider shapes only "
                             f"(slider.shape = \"{shape}\")")
    if ("E" in raw) != ("nu" in raw):
        raise InputError("slider.E and slider.nu go together: give both for an elastic "
                         "slider, neither for a rigid one")
    values = read_keys("slider", raw, [k for k in section_keys("slider", shape)
                                       if k.name not in ("E", "nu")])
    body = material("slider", {k: raw[k] for k in ("E", "nu")}, require_yield=False) \
        if "E" in raw else None
    slider = Slider(shape, values["radius"], values.get("length"), body,
                    str(values.get("name", "slider")))
    return slider, values["normal_load"]


def contact_friction(data: dict, base: Path | None = None) -> tuple[float, dict | None]:
    """The [contact] friction of a sliding scene: stated (``friction``), or the mean friction
    of a scratch record (``friction_from``, relative to ``base``), with where it came from."""
    contact = check_keys("contact", data.get("contact", {}), {FRICTION.name, FRICTION_FROM.name})
    if FRICTION_FROM.name not in contact:
        return FRICTION.read("contact", contact), None
    if FRICTION.name in contact:
        raise InputError("contact.friction and contact.friction_from both given: state the "
                         "friction or name the scratch record that measured it, not both")
    given = contact[FRICTION_FROM.name]
    if not isinstance(given, str) or not given:
        raise InputError(f"contact.friction_from = {given!r} must be the path of a scratch "
                         "record (text)")
    from filmscale.md.scratch_run import read_scratch_friction
    path = (Path(".") if base is None else Path(base)) / given
    measured = read_scratch_friction(path, "contact.friction_from")
    FRICTION.read("contact", {"friction": measured.mean})      # within the key's range
    return measured.mean, {"record": str(path), "mean": measured.mean, "std": measured.std,
                           "points": measured.points}


def _read(data: dict, pending=frozenset(), base: Path | None = None):
    """(slider, load, stack, friction, its source) of a sliding scene's data; the stack is
    None while a layer in ``pending`` awaits its calibration."""
    if "impactor" in data:
        raise InputError("the scene has an [impactor]: `filmscale slide` reads a sliding "
                         "scene with a [slider] (docs/sliding.md); impact scenes go to "
                         "`filmscale impact`")
    check_keys("scene", data, SECTIONS)
    slider, load = read_slider(data)
    stack = read_stack(data, pending)
    return (slider, load, stack, *contact_friction(data, base))


def slide_scene_from_data(data: dict, text: str = "", source: str = "<scene>",
                          base: Path | None = None) -> SlideScene:
    """Validate a sliding scene already read from TOML (``text`` kept for provenance;
    ``base``: the folder that relative file names use)."""
    slider, load, stack, friction, origin = _read(data, base=base)
    return SlideScene(slider, stack, load, friction, str(data.get("title", "")), text, source,
                      origin)


def check_slide_data(data: dict, pending=frozenset(), base: Path | None = None) -> None:
    """Every check of `slide_scene_from_data` on ``data``, whose layers in ``pending`` may
    still lack the E and sigma_y that their calibration will give (they must state nu)."""
    _read(data, pending, base)


def parse_slide_scene(text: str, source: str = "<scene>", base: Path | None = None
                      ) -> SlideScene:
    check_layer_headers(text)
    return slide_scene_from_data(parse_toml(text, "scene", source), text, source, base)


def load_slide_scene(path) -> SlideScene:
    """Read and validate a sliding scene file."""
    path = check_path("path", path)
    return parse_slide_scene(read_text(path, "scene"), source=str(path), base=path.parent)
