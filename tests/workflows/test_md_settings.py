"""The planner's reading of the measured MD speed-against-error table (rule 6): the bias of a
spec's settings, the preset's convergence, and the cheapest measured settings within a
tolerance. Oracle: the table's own rows (benchmarks/md_speed_vs_error.py), read by hand."""

import copy

import pytest

from filmscale.md.spec import PRESETS, spec_from_mapping
from filmscale.workflows import md_settings as ms


def _quick(**changes):
    data = copy.deepcopy(PRESETS["quick"])
    for key, value in changes.items():
        table, name = key.split("__")
        data[table][name] = value
    return spec_from_mapping(data)


def _row(key, value):
    return next(m for m in ms.TABLE if m.key == key and m.value == value)


def test_the_table_is_measured_against_the_presets_own_settings():
    spec = _quick()
    assert {k: ms._value(spec, k) for k in ms.REFERENCE} == ms.REFERENCE
    assert ms.settings_bias(spec) == ([], [])


def test_the_preset_is_the_cheapest_measured_setting_within_five_percent():
    """At 5 % the two cheaper rows (speed 200 m/s: -16 %, box 4.4 nm: -9.1 %) miss, the
    dearer ones move E by at most 3.8 % (speed 50 m/s) and the preset's own 2.2 % is below
    the tolerance: nothing to change, and the plan says so."""
    error, advice = ms.md_settings_advice(_quick(), 0.05)
    assert "carries 2.2%" in error and "up to +3.8% (speed 50 m/s)" in error
    assert advice == ("no cheaper measured setting keeps E within the tolerance 5%",)


def test_a_tight_tolerance_asks_for_an_ensemble_and_finer_settings():
    _, advice = ms.md_settings_advice(_quick(), 0.02)
    assert any("ask for an ensemble" in a for a in advice)
    assert any(a.startswith("speed 50 m/s (1.9 x the atom-steps) moved E by +3.8%")
               for a in advice)


def test_a_loose_tolerance_lists_the_cheaper_settings_cheapest_first():
    _, advice = ms.md_settings_advice(_quick(), 0.2)
    cheaper = [a for a in advice if a.startswith("cheaper")]
    assert cheaper == [
        "cheaper within the tolerance 20%: speed 200 m/s (0.55 x the atom-steps, E -16.0%)",
        "cheaper within the tolerance 20%: box 4.4 nm (0.56 x the atom-steps, E -9.1%)"]


def test_a_spec_off_the_preset_gets_its_measured_bias_or_is_named_unmeasured():
    fast = _quick(protocol__speed=200.0)
    known, unmeasured = ms.settings_bias(fast)
    assert known == [_row("protocol.speed", 200.0)] and unmeasured == []
    error, advice = ms.md_settings_advice(fast, 0.05)
    assert "this spec's speed 200 m/s: E -16.0%" in error
    assert advice[0] == "speed 200 m/s moved E by -16.0% in the table, more than the tolerance 5%"
    # its convergence is read from the other settings: the timestep's +3.2 %
    assert "up to +3.2% (timestep 2 fs)" in error
    other = _quick(protocol__speed=30.0, protocol__temperature=300.0)
    assert ms.settings_bias(other) == ([], ["speed 30 m/s", "temperature 300 K"])
    assert "not measured: speed 30 m/s, temperature 300 K" in ms.md_settings_advice(other,
                                                                                  0.05)[0]


@pytest.mark.parametrize("tolerance", [0.01, 0.05, 0.5])
def test_every_advice_names_the_tolerance(tolerance):
    _, advice = ms.md_settings_advice(_quick(), tolerance)
    assert advice and all(f"{tolerance:.0%}" in a for a in advice)


def test_the_plan_states_rule_6_for_an_md_source():
    from filmscale.workflows.plan import plan_scene
    from tests.helpers.scenes import scene
    step = plan_scene(scene(film='[target.layers.calibrate]\nmd = "quick"')).steps[0]
    assert "(rule 6)" in step.error and step.advice == ms.md_settings_advice(_quick(), 0.05)[1]
    assert "   advice: no cheaper measured setting" in plan_scene(
        scene(film='[target.layers.calibrate]\nmd = "quick"')).text()
