"""Scene texts shared by the tests, and the pipeline scene builder."""

from filmscale.workflows.pipeline_scene import parse_pipeline

#: the glass substrate of MINIMAL, CYLINDER_CALIBRATED and the BASE pipeline scenes
GLASS = """
[target.substrate]
name = "glass"
E = 90e9
nu = 0.25
sigma_y = 2.4e9
"""

#: a rigid sphere on bare glass, nothing more (tests/workflows/test_scene.py)
MINIMAL = """
[impactor]
shape = "sphere"
radius = 10e-6
mass = 1.6e-6
velocity = 0.2
""" + GLASS

#: a 1 mm x 5 mm rigid cylinder, 1 g at 5 m/s (tests/workflows/test_cylinder_cli.py)
CYLINDER_IMPACTOR = """
[impactor]
shape = "cylinder"
radius = 1e-3
length = 5e-3
mass = 1e-3
velocity = 5.0
"""

#: the steel substrate (sigma_y = 1 GPa) under CYLINDER_IMPACTOR
STEEL = """
[target.substrate]
name = "steel"
E = 200e9
nu = 0.3
sigma_y = 1e9
"""

#: CYLINDER_IMPACTOR on bare steel (tests/workflows/test_cylinder_cli.py)
CYLINDER_ON_STEEL = CYLINDER_IMPACTOR + STEEL

#: CYLINDER_ON_STEEL under a 30 um film (tests/workflows/test_long_command_logs.py)
CYLINDER_FILM_ON_STEEL = CYLINDER_ON_STEEL + """
[[target.layers]]
name = "film"
thickness = 30e-6
E = 120e9
nu = 0.25
sigma_y = 0.8e9
"""

#: CYLINDER_IMPACTOR at 2 m/s on glass under a 20 um film calibrated from film.csv, a
#: 3 x 2 map and want = maxima, map (tests/workflows/test_model_kind_commands.py)
CYLINDER_CALIBRATED = CYLINDER_IMPACTOR.replace("velocity = 5.0", "velocity = 2.0") + GLASS + """
[[target.layers]]
name = "film"
thickness = 20e-6
nu = 0.3
[target.layers.calibrate]
curves = ["film.csv"]
tip = "sphere:5um"

[map]
velocity = [0.5, 8.0, 3]
radius = [5e-4, 1e-3, 2]

[outputs]
want = ["maxima", "map"]
tolerance = 0.001
"""

#: a 1 mm elastic sphere on steel (sigma_y = 1.5 GPa), Hertz law, friction {mu}: format it
#: with mu (tests/workflows/test_oblique_cli.py)
OBLIQUE = """
[impactor]
radius = 1e-3
mass = 3.27e-5
velocity = 0.1

[target.substrate]
name = "steel"
E = 200e9
nu = 0.3
sigma_y = 1.5e9

[model]
contact_law = "hertz"

[contact]
friction = {mu}
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
