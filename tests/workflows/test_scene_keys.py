"""The declared scene keys drive the parser, the unit conversion and docs/scenes.md. Oracles:
the documentation's own text, scenes written here with each quantity in other units, and the
defaults stated in the docs against what a parsed scene holds."""

import re
from pathlib import Path

import pytest

from filmscale.core.errors import InputError
from filmscale.workflows.scene import parse_scene
from filmscale.workflows.scene_keys import GENERAL_KEYS, key_names, key_table, section_keys
from tests.helpers.scenes import MINIMAL

DOCS = Path(__file__).resolve().parents[2] / "docs" / "scenes.md"


def test_the_docs_key_list_is_the_declared_one():
    text = DOCS.read_text()
    start = text.index("| key | unit | required | valid | meaning |")
    end = text.index("<!-- end of the generated key list -->")
    assert text[start:end].strip() == key_table(), (
        "docs/scenes.md's key list differs from the declared keys: paste "
        "filmscale.workflows.scene_keys.key_table() there")


def test_every_documented_key_is_accepted_and_no_other():
    documented = re.findall(r"^\| `(\w+)` \|", DOCS.read_text(), re.MULTILINE)
    declared = {k.name for section in GENERAL_KEYS for k in section_keys(section)}
    assert set(documented) == declared
    with pytest.raises(InputError, match=r"unknown key impactor.colour"):
        parse_scene(MINIMAL.replace("velocity = 0.2", "velocity = 0.2\ncolour = 1"))


@pytest.mark.parametrize("key, text, si", [
    ("radius", '"10 um"', 10e-6), ("mass", '"1.6 mg"', 1.6e-6), ("velocity", '"20 cm/s"', 0.2),
    ("angle", '"0.5 rad"', 28.64788975654116),
])
def test_each_impactor_quantity_takes_units(key, text, si):
    scene_text = re.sub(rf"^{key} = .*$", f"{key} = {text}", MINIMAL, flags=re.MULTILINE)
    if key not in MINIMAL:
        scene_text = MINIMAL.replace("velocity = 0.2", f"velocity = 0.2\n{key} = {text}")
    imp = parse_scene(scene_text).impactor
    assert getattr(imp, key) == pytest.approx(si, rel=1e-12)


def test_the_documented_defaults_are_what_a_scene_holds():
    scene = parse_scene(MINIMAL)
    assert scene.law.name == "komvopoulos-ye" and scene.unloading == "auto"
    assert scene.model().unloading == "crater"          # the law's own default
    assert scene.path == "fast" and scene.rtol == 1e-8 and scene.friction == 0.0
    assert scene.impactor.angle == 0.0 and scene.impactor.inertia_factor == 0.4
    assert scene.map.spacing == "log"
    assert scene.model_target == "auto"             # rule 3 chooses (docs/pipeline.md)


def test_a_key_of_another_shape_names_the_shapes_that_read_it():
    with pytest.raises(InputError, match=r"impactor.datum_depth applies to cylinder impactors "
                                         r"only \(impactor.shape = \"sphere\"\)"):
        parse_scene(MINIMAL.replace("velocity = 0.2", "velocity = 0.2\ndatum_depth = 1e-3"))
    assert "contact_law" in key_names("model") and "friction" in key_names("contact")
