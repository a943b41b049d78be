"""The HDF5 record of an MD indentation: the curve in SI, the analysis, the potential's
elastic constants, the inputs and the provenance, written atomically."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from filmscale.continuum.indentation.io import read_curve_group, write_curve_group
from filmscale.core.files import atomic_h5
from filmscale.core.provenance import provenance as base_provenance
from filmscale.md.analysis import IndentAnalysis
from filmscale.md.elastic import ElasticConstants
from filmscale.md.engine import lammps_info
from filmscale.md.run import IndentRun

RECORD_FORMAT = "filmscale.md_indent/1"
RECORD_NAME = "indent.h5"


def write_attrs(group, values: dict):
    """Each value as an HDF5 attribute of ``group``: numbers and text as they are, anything
    else as JSON; None left out."""
    for key, value in values.items():
        if value is None:
            continue
        group.attrs[key] = value if isinstance(value, (int, float, str)) else json.dumps(value)


def run_provenance(run: IndentRun, extra: dict | None = None) -> dict[str, str | None]:
    """`filmscale.core.provenance.provenance` (filmscale, Python, numpy, scipy, h5py,
    platform, time, source revision) with LAMMPS's version and packages, the potential and
    its checksum, master and derived seeds, engine options, and ``extra``."""
    md = {**lammps_info(),
          "potential": run.spec.potential.name,
          "potential_file": run.spec.potential.file,
          "potential_sha256": run.spec.potential.sha256,
          "potential_citation": run.spec.potential.citation,
          "master_seed": run.spec.protocol.seed,
          "derived_seeds": json.dumps([p["seeds"] for p in run.parts]),
          "engine": json.dumps(run.engine)}
    md.update({k: str(v) for k, v in (extra or {}).items()})
    info = base_provenance(**{k: v for k, v in md.items() if v is not None})
    # a potential without a file or citation: None, which `write_record` leaves out
    info.update({k: None for k, v in md.items() if v is None})
    return info


def write_record(run: IndentRun, analysis: IndentAnalysis, elastic: ElasticConstants | None,
                 path: Path | str | None = None, provenance: dict | None = None) -> Path:
    """Write ``indent.h5`` (or ``path``): groups ``curve`` (filmscale.curve/1), ``analysis``
    (attributes in SI), ``contact``, ``elastic`` (C in Pa), ``inputs`` (every LAMMPS input as
    run, and the spec as JSON); provenance as root attributes."""
    path = Path(path) if path is not None else run.run_dir / RECORD_NAME
    with atomic_h5(path) as f:
        f.attrs["format"] = RECORD_FORMAT
        write_attrs(f, run_provenance(run, provenance))
        f.attrs["run_dir"] = str(run.run_dir)
        f.attrs["n_atoms"] = run.n_atoms
        f.attrs["n_steps"] = run.n_steps
        f.attrs["wall_time"] = run.wall_time
        f.attrs["z_surface"] = run.z_surface
        write_curve_group(f.create_group("curve"), run.curve)
        f["curve/step"] = run.steps
        a = f.create_group("analysis")
        d = analysis.to_dict()
        op = d.pop("op")
        write_attrs(a, {k: float(v) if isinstance(v, (float, np.floating)) else v
                   for k, v in d.items()})
        if op is not None:
            write_attrs(a.create_group("oliver_pharr"), op)
        if elastic is not None:
            e = f.create_group("elastic")
            e["C"] = elastic.C
            e["C"].attrs["units"] = "Pa"
            write_attrs(e, {k: v for k, v in elastic.to_dict().items() if k != "C"})
        inputs = f.create_group("inputs")
        for name, text in run.inputs().items():
            inputs[name] = text
        inputs["spec.json"] = json.dumps(run.spec.to_dict(), default=str)
        inputs.attrs["slab"] = json.dumps(run.spec.slab_built.to_dict())
        dumps = f.create_group("dumps")
        for step, dump in run.dumps:
            dumps.attrs[str(step)] = str(dump)
    return path


def read_record_curve(path: Path | str):
    """The load-displacement curve of a record (continuum's contract)."""
    import h5py
    with h5py.File(path, "r") as f:
        return read_curve_group(f["curve"])
