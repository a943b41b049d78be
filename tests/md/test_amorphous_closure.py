"""The disk scene with an MD-calibrated a-C overcoat, end to end (`examples/aC_overcoat_disk.
toml`, slow: about 3 min on 2 cores), and the closure of issue 36 at its size.

Oracles from outside the calibration: the block's own isotropic E, read from the quench unit's
record (its 6x6 C, Hill-averaged when the block was made); the store's units counted on disk;
the impact map's restitution against 1 (an elastic impact restitutes fully) where the map's
own first-yield flag says the contact yielded."""

import json
from pathlib import Path

import h5py
import numpy as np
import pytest

from filmscale.md.amorphous_run import RECORD_NAME, read_amorphous_summary
from filmscale.workflows.pipeline import run_scene
from filmscale.workflows.pipeline_scene import load_pipeline

SCENE = Path(__file__).resolve().parents[2] / "examples" / "aC_overcoat_disk.toml"

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def ran(tmp_path_factory):
    root = tmp_path_factory.mktemp("disk")
    result = run_scene(load_pipeline(SCENE), root / "store", root / "out.h5")
    blocks = sorted((root / "store").glob("md-amorphous-*[!.lock]"))
    indents = sorted((root / "store").glob("md-indent-*[!.lock]"))
    with h5py.File(result.path, "r") as f:
        cal = {k: f["calibration/0"].attrs[k] for k in ("E", "E_std", "E_identified")}
    return result, blocks, indents, cal


def test_the_disk_scene_quenches_calibrates_and_maps_its_overcoat(ran):
    result, blocks, indents, cal = ran
    assert len(blocks) == 1 and len(indents) == 1
    first = result.plan.steps[0]
    assert first.model.startswith("a melt-quench of its film (recipe ci-aC, 512 atoms, 3 g/cm3")
    # the MD unit's record holds the block's own E for the film (the closure's reference)
    record = json.loads((indents[0] / "done.json").read_text())
    top = record["potential_elastic"]["top"]
    block = read_amorphous_summary(blocks[0] / RECORD_NAME)
    assert top["structure"] == "amorphous" and top["E"] == pytest.approx(block["E"], rel=1e-9)
    assert cal["E_identified"] and 0 < cal["E_std"] < 0.2 * cal["E"]
    # the film's drop is no pop-in (the loading climbs back onto the elastic law), and the
    # slab's rigid base is in the exact elastic branch, so no warning says it reads E high
    with h5py.File(result.path, "r") as f:
        warnings = json.loads(f["calibration/0"].attrs["calibration"])["warnings"]
    assert any("not followed by yield" in w for w in warnings)
    assert any("exact layered solution" in w and "rigid base" in w for w in warnings)
    assert not any("reads" in w and "high" in w for w in warnings)
    # the map yields somewhere (rule 4 keeps the law), and restitution falls there
    with h5py.File(result.path, "r") as f:
        e = f["impact/map/restitution"][()]
        yielded = f["impact/map/yielded"][()].astype(bool)
    assert yielded.any() and np.nanmax(e[yielded]) < 1.0
    assert np.nanmin(e[~yielded]) == pytest.approx(1.0, abs=1e-9)


def test_at_the_scenes_size_the_films_calibrated_e_is_its_blocks_within_10_percent(ran):
    """One quench seed at the ci size, the slab's base in the model: 0.96 of the block
    (1.15 before the base entered the model). The ci seeds scatter widely, so this is the
    scene's check, not the issue's closure (the quick block's film under a 5 nm sphere, 0.967
    +- 0.007 over three seeds: docs/amorphous.md, Closure)."""
    _, blocks, _, cal = ran
    block_E = read_amorphous_summary(blocks[0] / RECORD_NAME)["E"]
    assert cal["E"] == pytest.approx(block_E, rel=0.10)
