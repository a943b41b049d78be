"""Rule 4 over a whole map: the planner keeps the scene's contact law whenever any point of
the map yields, not only when a corner does. The case: a 3 nm overcoat of 429 GPa (an MD
calibration's E, its sigma_y a lower bound of 158 GPa) over 16 nm of CoCrPt on glass, mapped
over 0.01-5 m/s and 20 nm-10 um: the fastest small corner is out of range (approach > R),
the fastest large corner does not yield, and the middle of the fastest column does.
Oracle: the scene's own law evaluated at every radius of the map's fastest column
(`ImpactModel.maxima` directly, not through the planner)."""

import numpy as np

from filmscale.workflows.pipeline_scene import parse_pipeline
from filmscale.workflows.plan import plan_scene

SCENE = """
title = "overcoat"
[impactor]
radius = 1e-6
mass = 1e-12
velocity = 0.5
[target.substrate]
name = "glass"
E = 90e9
nu = 0.25
sigma_y = 2.4e9
[[target.layers]]
name = "a-C"
thickness = 3e-9
E = 429e9
nu = 0.14
sigma_y = 157.7e9
[[target.layers]]
name = "CoCrPt"
thickness = 16e-9
E = 180e9
nu = 0.3
sigma_y = 5e9
[model]
contact_law = "komvopoulos-ye-continuous"
[outputs]
want = ["maxima", "map"]
[map]
velocity = [0.01, 5.0, 30]
radius = [2e-8, 1e-5, 30]
spacing = "log"
"""


def test_a_map_that_yields_inside_its_fastest_column_keeps_the_scenes_law():
    pipeline = parse_pipeline(SCENE)
    scene = pipeline.completed({})
    v_axis, r_axis = scene.map.axes()
    grid = scene.model().maxima(np.full(r_axis.size, v_axis[-1]), r_axis, scene.impactor.mass)
    in_range = np.isfinite(grid.delta_max)
    yielded = np.asarray(grid.yielded) & in_range
    # the case as stated: the corners miss the yield that the middle of the column finds
    assert not in_range[0] and not yielded[-1] and yielded.any()
    law = next(s for s in plan_scene(pipeline).steps if s.name == "contact law")
    assert law.model == "komvopoulos-ye-continuous"
    assert law.reason.startswith("first yield is reached at")


def test_a_map_that_never_yields_still_goes_to_the_closed_form():
    """Rule 4 unchanged where nothing yields: the same stack mapped at 0.1-1 mm/s."""
    pipeline = parse_pipeline(SCENE.replace("velocity = [0.01, 5.0, 30]",
                                            "velocity = [1e-4, 1e-3, 5]"))
    scene = pipeline.completed({})
    v_axis, r_axis = scene.map.axes()
    grid = scene.model().maxima(np.full(r_axis.size, v_axis[-1]), r_axis, scene.impactor.mass)
    assert not np.any(np.asarray(grid.yielded) & np.isfinite(grid.delta_max))
    law = next(s for s in plan_scene(pipeline).steps if s.name == "contact law")
    assert law.model == "Hertz (closed form)"
