"""The finite-element cases of Dao et al. (2001) and Chollacoop et al. (2003) shipped with
the package (data/dao2001, compiled by Lu et al. 2020, PNAS 117, 7052; Apache-2.0)."""

from __future__ import annotations

import functools
from importlib import resources

import numpy as np

from filmscale.continuum.indentation.io import read_table
from filmscale.continuum.indentation.reverse.functions import (EPS_R_DAO, FE_DEPTH, FE_NU,
                                                               representative_stress,
                                                               sharp_calibration)
from filmscale.core.checks import check_choice

# --- packaged data ----------------------------------------------------------------------------

#: column names of the packaged CSVs (units in the header: GPa, N/m, um) -> key
_KEYS = {"Case": "case", "n": "n", "E": "E", "sy": "sigma_y", "C": "C", "dP/dh": "dPdh",
         "Wp/Wt": "WpWt", "E*": "E_star", "hm": "h_m", "s0.033": "sigma_0.033",
         "s0.066": "sigma_0.066", "s0.1": "sigma_0.1"}
DATA_FILES = ("Berkovich.csv", "FEM_50deg.csv", "FEM_60deg.csv", "FEM_70deg.csv",
              "FEM_80deg.csv", "Al6061.csv")


@functools.cache
def cached_dao2001_table(name: str) -> dict:
    """Columns of a packaged file in SI by key, read-only (shared by every caller)."""
    source = resources.files("filmscale.continuum.indentation.reverse") / "data" / "dao2001"
    with resources.as_file(source / name) as path:
        columns = read_table(path)
    cols = {}
    for title, values in columns.items():
        cols[_KEYS[title]] = values
        values.flags.writeable = False
    return cols


def dao2001_table(name: str) -> dict[str, np.ndarray]:
    """Columns of a packaged ``data/dao2001`` file in SI (Pa, N/m, m); NaN for blanks.

    Keys: case, n, E, sigma_y, C, dPdh, WpWt (FE files); C, dPdh, WpWt, E_star, sigma_y, h_m,
    sigma_0.033, sigma_0.066, sigma_0.1, n (Al6061.csv). Data: Lu et al. (2020), Apache-2.0.
    """
    check_choice("data file", name, DATA_FILES)
    return {k: v.copy() for k, v in cached_dao2001_table(name).items()}


#: FE files with C, dP/dh and W_p/W_t, their tip and c*
FE_REVERSE_FILES = (("Berkovich.csv", "berkovich"), ("FEM_70deg.csv", "cone:70.3"))


@functools.cache
def fe_reverse_cases() -> dict:
    """Pooled FE cases usable for the reverse analysis, with true E* and sigma_0.033."""
    parts = {k: [] for k in ("file", "case", "tip", "c_star", "n", "E", "sigma_y", "C", "dPdh",
                             "WpWt")}
    for name, tip in FE_REVERSE_FILES:
        t = cached_dao2001_table(name)
        m = t["C"].size
        parts["file"] += [name] * m
        parts["tip"] += [tip] * m
        parts["c_star"].append(np.full(m, sharp_calibration(tip).c_star))
        for k in ("case", "n", "E", "sigma_y", "C", "dPdh", "WpWt"):
            parts[k].append(t[k])
    d = {k: (np.array(v) if k in ("file", "tip") else np.concatenate(v))
         for k, v in parts.items()}
    d["E_star"] = d["E"] / (1.0 - FE_NU**2)
    d["sigma_r"] = representative_stress(d["E"], d["sigma_y"], d["n"], EPS_R_DAO)
    d["h_m"] = np.full(d["C"].size, FE_DEPTH)
    # one group per material: the Berkovich cases repeat 70-deg materials and must be held out
    # together, or a fold would test on a material it trained on
    key = np.round(np.c_[d["n"], d["E"] / 1e9, d["sigma_y"] / 1e9], 4)
    _, d["group"] = np.unique(key, axis=0, return_inverse=True)
    d["group"] = d["group"].ravel()
    return d
