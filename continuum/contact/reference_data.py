"""Published measurements and finite-element results of oblique sphere impact, for validation.

Values are as digitised from the papers' figures by others (named per set); angles in degrees,
spins in rad/s, SI otherwise. `benchmarks/oblique_validation.py` and
`tests/continuum/test_oblique_references.py` compare the oblique model with them.
"""

from __future__ import annotations

#: Kharaz, Gorham & Salman (2001, Powder Technol. 120, 281): 5 mm alumina spheres on a thick
#: soda-lime glass anvil at 3.9 m/s, the angle from the normal; the paper reports close
#: agreement with Maw, Barber & Fawcett's theory. Digitised for the MFIX DEM05 verification
#: case. Pairs are (incidence angle, measured value).
KHARAZ_2001 = {
    "sphere": {"E": 380e9, "nu": 0.23, "density": 4000.0, "radius": 2.5e-3},
    "anvil": {"E": 70e9, "nu": 0.25},
    "friction": 0.092,
    "speed": 3.9,
    "restitution_tangential": [(2.03, 0.794), (3.93, 0.745), (9.63, 0.673), (20.08, 0.596),
                               (30.22, 0.688), (39.30, 0.772), (49.55, 0.847), (59.84, 0.902)],
    "rebound_angle": [(0.24, 0.12), (2.29, 1.76), (4.29, 2.96), (9.94, 6.69), (20.56, 12.36),
                      (30.38, 21.78), (39.62, 32.55), (49.78, 45.11), (60.06, 57.37)],
    "spin": [(6.00, 135.6), (10.98, 264.5), (21.19, 577.0), (31.09, 612.6), (39.03, 595.5),
             (50.22, 452.9), (60.25, 381.3)],
}

#: Chung & Ooi (2011, Granular Matter 13, 643), test 5: an elastic sphere on a rigid plane at
#: mu = 0.3 and 5 m/s normal speed, finite elements; digitised for the Kratos DEM benchmarks.
#: Pairs are (x, y): x = V_t / (mu V_n) before impact, y = the contact point's tangential
#: speed over mu times the normal speed after it. The data do not say which of the test's two
#: materials they show (steel, nu = 0.3, or polyethylene, nu = 0.4).
CHUNG_OOI_2011_TEST5 = {
    "friction": 0.3,
    "poisson_ratios": (0.3, 0.4),
    "recoil": [(0.876, -0.080), (1.190, -0.213), (1.553, -0.373), (1.915, -0.627),
               (2.314, -0.947), (2.785, -1.253), (3.317, -1.520), (3.970, -1.720),
               (4.755, -1.707), (5.758, -1.200), (7.124, 0.133), (9.118, 2.147),
               (12.356, 5.427)],
}
