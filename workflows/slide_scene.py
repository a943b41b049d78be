"""Sliding scenes (TOML): a slider's protrusion held at a normal load and sliding with friction
on a target stack (`filmscale slide`, `slide-map`; docs/sliding.md).

A sliding scene holds [slider] (shape, radius, length of a cylinder, normal_load, optional E
and nu of an elastic slider), [target] as an impact scene's and [contact] friction. Every key
is checked before any work starts, with the messages of the impact scenes (docs/scenes.md).
"""

from __future__ import annotations

from dataclasses import dataclass

from filmscale.continuum.contact.slider import Slider
from filmscale.continuum.materials import LayerStack
from filmscale.core.checks import check_keys, check_path, required
from filmscale.core.errors import InputError
from filmscale.core.files import parse_toml, read_text
from filmscale.core.keys import Key, read_keys
from filmscale.core.quantities import to_si

from .scene import check_layer_headers, material, read_stack
from .scene_keys import key_names, quantity_units, section_keys

#: [contact] of a sliding scene
FRICTION = Key("friction", "1", 0.0, 0.0, 10.0, section="contact",
               doc="Coulomb coefficient mu of the sliding contact (q = mu p)")
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


def _read(data: dict, pending=frozenset()):
    """(slider, load, stack, friction) of a sliding scene's data; the stack is None while a
    layer in ``pending`` awaits its calibration."""
    if "impactor" in data:
        raise InputError("the scene has an [impactor]: `filmscale slide` reads a sliding "
                         "scene with a [slider] (docs/sliding.md); impact scenes go to "
                         "`filmscale impact`")
    check_keys("scene", data, SECTIONS)
    slider, load = read_slider(data)
    stack = read_stack(data, pending)
    contact = check_keys("contact", data.get("contact", {}), {FRICTION.name})
    return slider, load, stack, FRICTION.read("contact", contact)


def slide_scene_from_data(data: dict, text: str = "", source: str = "<scene>") -> SlideScene:
    """Validate a sliding scene already read from TOML (``text`` kept for provenance)."""
    slider, load, stack, friction = _read(data)
    return SlideScene(slider, stack, load, friction, str(data.get("title", "")), text, source)


def check_slide_data(data: dict, pending=frozenset()) -> None:
    """Every check of `slide_scene_from_data` on ``data``, whose layers in ``pending`` may
    still lack the E and sigma_y that their calibration will give (they must state nu)."""
    _read(data, pending)


def parse_slide_scene(text: str, source: str = "<scene>") -> SlideScene:
    check_layer_headers(text)
    return slide_scene_from_data(parse_toml(text, "scene", source), text, source)


def load_slide_scene(path) -> SlideScene:
    """Read and validate a sliding scene file."""
    path = check_path("path", path)
    return parse_slide_scene(read_text(path, "scene"), source=str(path))
