"""What an MD indentation's settings cost and what they do to the calibrated film E: the table
that ``benchmarks/md_speed_vs_error.py`` measured on the quick preset, and the planner's
reading of it for a calibration source.

The planner does not change a spec: its loading speed and temperature are physics the user
chose (the pop-in load moves with both). For each MD source it states the bias the table
gives the spec's settings, the seed-to-seed scatter they sit on, the settings whose measured
effect exceeds the scene's tolerance, and the cheapest measured settings within it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from filmscale.md.indentation import IndentProtocol
from filmscale.md.spec import PRESETS

#: the preset the table was measured on, and its value of each setting the table varies
PRESET = "quick"
SETTING_KEYS = ("protocol.speed", "protocol.timestep", "protocol.temperature",
                "slab.lateral_size")


def _preset_value(key: str) -> float:
    table, name = key.split(".")
    value = PRESETS[PRESET][table].get(name)
    return float(getattr(IndentProtocol, name) if value is None else value)


REFERENCE = {key: _preset_value(key) for key in SETTING_KEYS}
#: how each setting is named and shown
SETTINGS = {"protocol.speed": ("speed", 1.0, "m/s"), "protocol.timestep": ("timestep", 1e15, "fs"),
            "protocol.temperature": ("temperature", 1.0, "K"),
            "slab.lateral_size": ("box", 1e9, "nm")}


@dataclass(frozen=True)
class Measured:
    """One setting changed from the preset: the film E's relative change and the cost."""

    key: str         #: the spec field, "protocol.speed", ...
    value: float     #: its value in the run (SI)
    dE: float        #: (E - E_preset) / E_preset of the calibrated film E
    cost: float      #: atom-steps over the preset's

    def text(self) -> str:
        name, scale, unit = SETTINGS[self.key]
        return f"{name} {self.value * scale:g} {unit}"


#: measured by benchmarks/md_speed_vs_error.py on 2 ranks (docs/md-indentation.md, "Speed
#: against error"): the preset's film E is 133.6 +- 2.9 GPa; cost is atom-steps over the
#: preset's 7.88e7
TABLE: tuple[Measured, ...] = (
    Measured("protocol.speed", 200.0, -0.160, 0.546),
    Measured("protocol.speed", 50.0, 0.038, 1.916),
    Measured("protocol.timestep", 2e-15, 0.032, 2.005),
    Measured("protocol.temperature", 100.0, -0.118, 1.0),
    Measured("slab.lateral_size", 4.4e-9, -0.091, 0.563),
)
#: the preset's own E uncertainty, relative: its fit's std (a second seed lay 0.7 % away)
NOISE = 0.022


def _value(spec, key: str) -> float:
    table, name = key.split(".")
    return float(getattr(getattr(spec, table), name))


def settings_bias(spec) -> tuple[list[Measured], list[str]]:
    """(the table's rows for the spec's settings that differ from the preset, the names of
    differing settings the table has not measured)."""
    known, unmeasured = [], []
    for key, ref in REFERENCE.items():
        value = _value(spec, key)
        if math.isclose(value, ref, rel_tol=1e-9):
            continue
        row = next((m for m in TABLE if m.key == key
                    and math.isclose(m.value, value, rel_tol=1e-9)), None)
        if row is None:
            name, scale, unit = SETTINGS[key]
            unmeasured.append(f"{name} {value * scale:g} {unit}")
        else:
            known.append(row)
    return known, unmeasured


def md_settings_advice(spec, tolerance: float) -> tuple[str, tuple[str, ...]]:
    """(the error statement, advice lines) of an MD spec against the measured table, for a
    relative tolerance on the film's E (the scene's tolerance)."""
    if any(film.structure == "amorphous" for film in spec.slab.films):
        return (f"MD settings: not measured for an amorphous film (the table is of the "
                f"{PRESET} preset's crystal film); the quench's own rate and size against sp3 "
                "and E are in docs/amorphous.md"), ()
    known, unmeasured = settings_bias(spec)
    changed = {m.key for m in known}
    dearer = [m for m in TABLE if m.cost > 1.0 and m.key not in changed]
    convergence = max(dearer, key=lambda m: abs(m.dE), default=None)
    error = (f"MD settings, from the table measured on the {PRESET} preset: its E carries "
             f"{NOISE:.1%}" + ("" if convergence is None else
                               f", dearer settings move it by up to {convergence.dE:+.1%} "
                               f"({convergence.text()})")
             + "".join(f"; this spec's {m.text()}: E {m.dE:+.1%}" for m in known)
             + (f"; not measured: {', '.join(unmeasured)}" if unmeasured else ""))
    advice = [f"{m.text()} moved E by {m.dE:+.1%} in the table, more than the tolerance "
              f"{tolerance:.0%}" for m in known if abs(m.dE) > tolerance]
    if NOISE > tolerance:
        advice.append(f"one run's E carries {NOISE:.1%}, more than the tolerance "
                      f"{tolerance:.0%}: ask for an ensemble (seeds = N)")
    if convergence is not None and abs(convergence.dE) > tolerance:
        advice.append(f"{convergence.text()} ({convergence.cost:.2g} x the atom-steps) moved "
                      f"E by {convergence.dE:+.1%}, more than the tolerance {tolerance:.0%}: "
                      "the settings are not converged to it")
    cheaper = sorted((m for m in TABLE if m.cost < 1.0 and m.key not in changed
                      and abs(m.dE) <= tolerance), key=lambda m: m.cost)
    advice += [f"cheaper within the tolerance {tolerance:.0%}: {m.text()} ({m.cost:.2g} x "
               f"the atom-steps, E {m.dE:+.1%})" for m in cheaper]
    if not cheaper:
        advice.append(f"no cheaper measured setting keeps E within the tolerance "
                      f"{tolerance:.0%}")
    return error, tuple(advice)
