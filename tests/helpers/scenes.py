"""Scene texts shared by the tests, and the pipeline scene builder."""

from filmscale.workflows.pipeline_scene import parse_pipeline

#: a rigid sphere on bare glass, nothing more (tests/workflows/test_scene.py)
MINIMAL = """
[impactor]
shape = "sphere"
radius = 10e-6
mass = 1.6e-6
velocity = 0.2

[target.substrate]
name = "glass"
E = 90e9
nu = 0.25
sigma_y = 2.4e9
"""

#: MINIMAL, slower (0.05 m/s), with a 3 x 3 impact map (tests/workflows/test_hostile_cli.py)
SCENE = MINIMAL.replace("velocity = 0.2", "velocity = 0.05") + """
[map]
velocity = [0.01, 1.0, 3]
radius = [1e-6, 1e-5, 3]
"""

#: an elastic diamond-like sphere on glass under the Hertz law (tests/workflows/test_cli.py)
HERTZ_SCENE = """
[impactor]
radius = 10e-6
mass = 1.6e-6
velocity = 0.05
E = 400e9
nu = 0.23

[target.substrate]
name = "glass"
E = 90e9
nu = 0.25
sigma_y = 2.4e9

[model]
contact_law = "hertz"
"""

#: a pipeline scene with one film on glass; format it with R, m, V, t, impactor_extra, film
#: and want (tests/workflows/test_pipeline.py)
BASE = """
[impactor]
radius = {R}
mass = {m}
velocity = {V}
{impactor_extra}
[target.substrate]
name = "glass"
E = 90e9
nu = 0.25
sigma_y = 2.4e9
[[target.layers]]
name = "film"
thickness = {t}
nu = 0.3
{film}
[outputs]
want = {want}
tolerance = 0.05
"""

#: a BASE film calibrated from film.csv (curves.sphere_curve_file) under a 5 um sphere
CURVES_FILM = '[target.layers.calibrate]\ncurves = ["film.csv"]\ntip = "sphere:5um"'


def scene(R=10e-6, m=1.6e-6, V=0.2, t=4e-9, film='E = 200e9\nsigma_y = 8e9',
          want='["maxima"]', impactor_extra=""):
    """BASE with these values, parsed."""
    return parse_pipeline(BASE.format(R=R, m=m, V=V, t=t, film=film, want=want,
                                         impactor_extra=impactor_extra))
