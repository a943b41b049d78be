"""Property-depth profiles from a set of indents: E_r(h_c) and H(h_c) with scatter, per layer.

A film is characterised by indents at increasing depth (repeats at each load). This module
groups the repeats, gives mean and standard deviation of E_r and H at each depth, assigns
every indent to the layer that contains its contact depth, and fits continuous piecewise
lines with the layer interfaces as breakpoints: the `TableProfile` that the impact model takes,
so measured or simulated indentation feeds impact directly.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from filmscale.continuum.contact.profiles import TableProfile
from filmscale.continuum.materials import DIAMOND, ElasticPlastic, LayerStack
from filmscale.core.checks import check_positive
from filmscale.core.errors import InputError

#: repeats whose contact depths differ by less than this fraction form one depth group
GROUP_TOLERANCE = 0.1


@dataclass(frozen=True)
class PropertyDepthProfile:
    """Indentation properties against contact depth, grouped by depth and by layer."""

    h_c: np.ndarray          #: contact depth of each indent, m
    E_r: np.ndarray          #: reduced modulus of each indent, Pa
    H: np.ndarray            #: hardness of each indent, Pa
    layer: np.ndarray        #: index of the layer holding each h_c (len(interfaces): substrate)
    interfaces: tuple        #: depths of the layer interfaces, m, top first
    layer_names: tuple       #: one name per layer and the substrate last
    group_h_c: np.ndarray    #: mean contact depth of each depth group, m
    group_E_r: np.ndarray    #: mean E_r of each group, Pa
    group_E_r_std: np.ndarray  #: sample standard deviation of E_r in each group (0 if alone), Pa
    group_H: np.ndarray      #: mean H of each group, Pa
    group_H_std: np.ndarray  #: sample standard deviation of H in each group, Pa
    group_n: np.ndarray      #: indents in each group

    def layer_statistics(self) -> list[dict]:
        """Mean and standard deviation of E_r and H (Pa) of the indents in each layer."""
        out = []
        for k, name in enumerate(self.layer_names):
            sel = self.layer == k
            n = int(sel.sum())
            row = {"layer": name, "n": n}
            for key, values in (("E_r", self.E_r), ("H", self.H)):
                v = values[sel]
                row[key] = float(v.mean()) if n else None
                row[f"{key}_std"] = float(v.std(ddof=1)) if n > 1 else None
            out.append(row)
        return out

    def to_depth_profile(self, *, indenter: ElasticPlastic | None = DIAMOND, nu=0.3,
                         hardness_factor=2.8) -> TableProfile:
        """The piecewise-linear depth profile of the impact model.

        Continuous piecewise-linear least squares through every indent, with the layer
        interfaces as breakpoints; E_r is converted to the target's plane-strain modulus by
        removing the indenter's compliance; sigma_y = H / k_T with k_T = ``hardness_factor``
        (pass the contact law's). See `TableProfile.from_measurements`.
        """
        return TableProfile.from_measurements(self.h_c, self.E_r, self.H,
                                              breakpoints=self.interfaces, indenter=indenter,
                                              nu=nu, hardness_factor=hardness_factor)

    def to_dict(self) -> dict:
        return {"h_c": self.h_c.tolist(), "E_r": self.E_r.tolist(), "H": self.H.tolist(),
                "layer": self.layer.tolist(), "interfaces": list(self.interfaces),
                "layer_names": list(self.layer_names), "groups": {
                    "h_c": self.group_h_c.tolist(), "E_r": self.group_E_r.tolist(),
                    "E_r_std": self.group_E_r_std.tolist(), "H": self.group_H.tolist(),
                    "H_std": self.group_H_std.tolist(), "n": self.group_n.tolist()},
                "layers": self.layer_statistics()}

    def summary(self) -> str:
        lines = [f"{self.h_c.size} indents in {self.group_n.size} depth groups"]
        for row in self.layer_statistics():
            if row["n"]:
                std = row["H_std"]
                lines.append(f"  {row['layer']}: {row['n']} indents, E_r = "
                             f"{row['E_r'] / 1e9:.4g} GPa, H = {row['H'] / 1e9:.4g} GPa"
                             + (f" +- {std / 1e9:.2g}" if std is not None else ""))
        return "\n".join(lines)


def _groups(h_c, tolerance):
    order = np.argsort(h_c)
    hs = h_c[order]
    breaks = np.flatnonzero(hs[1:] > hs[:-1] * (1.0 + tolerance)) + 1
    label = np.zeros(h_c.size, dtype=int)
    label[order] = np.cumsum(np.isin(np.arange(h_c.size), breaks))
    return label


def property_profile(h_c, E_r, H, *, layers: LayerStack | None = None, interfaces=(),
                     layer_names=(), group_tolerance=GROUP_TOLERANCE) -> PropertyDepthProfile:
    """Group indents by depth and by layer.

    Parameters
    ----------
    h_c, E_r, H : array_like
        Contact depth (m), reduced modulus (Pa) and hardness (Pa) of each indent; indents
        whose values are not finite and positive (failed analyses) are left out.
    layers : LayerStack, optional
        Gives the interfaces and layer names; or give them directly:
    interfaces : sequence of float
        Depths of the layer interfaces (m), increasing from the surface.
    layer_names : sequence of str
        One per layer plus the substrate.
    group_tolerance : float
        Indents whose sorted contact depths step by less than this fraction are repeats
        of one depth.
    """
    h_c, E_r, H = (np.asarray(v, dtype=float).ravel() for v in (h_c, E_r, H))
    if not (h_c.size == E_r.size == H.size):
        raise InputError(f"h_c, E_r and H differ in length: {h_c.size}, {E_r.size}, {H.size}")
    ok = np.isfinite(h_c) & np.isfinite(E_r) & np.isfinite(H) & (h_c > 0) & (E_r > 0) & (H > 0)
    h_c, E_r, H = h_c[ok], E_r[ok], H[ok]
    if h_c.size < 2:
        raise InputError(f"a property-depth profile needs at least 2 analysed indents, "
                         f"got {h_c.size}")
    check_positive("group_tolerance", group_tolerance)
    if layers is not None:
        interfaces = layers.interface_depths
        layer_names = tuple(layer.material.name or f"layer {k + 1}"
                            for k, layer in enumerate(layers.layers)) + (
            layers.substrate.name or "substrate",)
    interfaces = tuple(float(z) for z in interfaces)
    if any(not math.isfinite(z) or z <= 0 for z in interfaces) or \
            any(b <= a for a, b in zip(interfaces, interfaces[1:])):
        raise InputError(f"interfaces = {list(interfaces)} must be positive depths (m), "
                         f"increasing from the surface")
    if not layer_names:
        layer_names = tuple(f"layer {k + 1}" for k in range(len(interfaces))) + ("substrate",)
    if len(layer_names) != len(interfaces) + 1:
        raise InputError(f"{len(layer_names)} layer names for {len(interfaces)} interfaces: "
                         f"give one name per layer and one for the substrate")
    layer = np.searchsorted(np.asarray(interfaces), h_c, side="right")
    group = _groups(h_c, group_tolerance)
    n_groups = int(group.max()) + 1
    stats = {key: np.zeros(n_groups) for key in ("h", "E", "Es", "H", "Hs", "n")}
    for g in range(n_groups):
        sel = group == g
        n = int(sel.sum())
        stats["n"][g] = n
        stats["h"][g] = h_c[sel].mean()
        stats["E"][g], stats["H"][g] = E_r[sel].mean(), H[sel].mean()
        stats["Es"][g] = E_r[sel].std(ddof=1) if n > 1 else 0.0
        stats["Hs"][g] = H[sel].std(ddof=1) if n > 1 else 0.0
    return PropertyDepthProfile(h_c, E_r, H, layer, interfaces, tuple(layer_names), stats["h"],
                                stats["E"], stats["Es"], stats["H"], stats["Hs"],
                                stats["n"].astype(int))
