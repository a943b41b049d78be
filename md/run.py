"""Running an indentation: run directory, checkpoints, resumption and the load-displacement
curve in SI.

A run directory holds the data file, the input of the fresh run (``in.indent``), one input per
resumption (``in.resume.1``, ...), the record of each part (``indent.dat``, ``indent.1.dat``,
...), restart files, dumps and ``state.json``, which lists the parts. Files once written are
never rewritten: a resumption starts a new part from the newest readable restart file, and the
curve keeps, for every step, the row of the latest part that reached it.
"""

from __future__ import annotations

import json
import re
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from ase.io import write as ase_write

from filmscale import __version__
from filmscale.continuum.indentation.curves import LoadDisplacementCurve
from filmscale.core.checks import check_path
from filmscale.core.errors import InputError
from filmscale.core.files import read_json, write_json
from filmscale.core.jsonable import to_jsonable
from filmscale.md.amorphous_film import check_made
from filmscale.md.engine import EngineOptions, LammpsError, parse_table, run_input
from filmscale.md.indentation import (DATA_FILE, RECORD_COLUMNS, SURFACE_FILE, IndentSpec,
                                      derive_seeds, indentation_input, resume_input)
from filmscale.md.lammps_input import write_input
from filmscale.md.lammps_units import lammps_to_si

STATE_FILE = "state.json"
_RESTART = re.compile(r"^restart\.(\d+)\.bin$")


@dataclass(frozen=True)
class IndentRun:
    """A finished indentation run: the curve in SI and where everything else lies."""

    spec: IndentSpec
    run_dir: Path
    curve: LoadDisplacementCurve   #: h (m) from the undeformed surface, P (N), t (s)
    z_surface: float               #: height of the undeformed surface in the box, m
    steps: np.ndarray              #: LAMMPS timestep of each curve point
    parts: tuple[dict, ...]        #: one entry per fresh or resumed part, as run
    dumps: tuple[tuple[int, Path], ...]   #: (timestep, file) of each dump
    wall_time: float               #: seconds spent in LAMMPS over all parts
    engine: dict = field(default_factory=dict)

    @property
    def n_atoms(self) -> int:
        return self.spec.slab_built.n_atoms

    @property
    def n_steps(self) -> int:
        return self.spec.protocol.schedule().s_end

    def inputs(self) -> dict[str, str]:
        """Input file name -> text, in the order they ran."""
        return {p["input"]: (self.run_dir / p["input"]).read_text() for p in self.parts}


def restart_files(run_dir: Path) -> list[tuple[int, Path]]:
    """(step, path) of each restart file in ``run_dir``, the newest first."""
    found = [(int(m.group(1)), p) for p in run_dir.iterdir()
             if (m := _RESTART.match(p.name))]
    return sorted(found, reverse=True)


def _spec_dict(spec: IndentSpec) -> dict:
    """The spec as its JSON files hold it (objects without a JSON form as text)."""
    return to_jsonable(json.loads(json.dumps(spec.to_dict(), default=str)))


def _fresh(spec: IndentSpec, run_dir: Path) -> dict:
    ase_write(run_dir / DATA_FILE, spec.slab_built.atoms, format="lammps-data",
              specorder=list(spec.type_elements), masses=True, units="metal",
              atom_style="atomic")
    write_input(run_dir / "in.indent", indentation_input(spec, version=__version__))
    write_json(run_dir / "spec.json", _spec_dict(spec))
    seeds = derive_seeds(spec.protocol.seed, ("velocity", "langevin"))
    return {"input": "in.indent", "record": "indent.dat", "start": 0, "seeds": seeds}


def _resume_part(spec: IndentSpec, run_dir: Path, k: int, step: int, restart: Path) -> dict:
    z_surface = float((run_dir / SURFACE_FILE).read_text().split()[0])
    name, record = f"in.resume.{k}", f"indent.{k}.dat"
    write_input(run_dir / name, resume_input(
        spec, restart_file=restart.name, restart_step=step, z_surface=z_surface, part=k,
        record=record, version=__version__))
    return {"input": name, "record": record, "start": step, "restart": restart.name,
            "seeds": derive_seeds(spec.protocol.seed, ("langevin",), part=k)}


def run_resumable(run_dir: Path, spec_dict: dict, total: int, fresh: Callable[[], dict],
                  resume: Callable[[int, int, Path], dict], engine: EngineOptions,
                  progress: Callable[[int, int], None] | None = None) -> None:
    """Run the LAMMPS parts of a run directory until it is finished: a new directory starts
    with ``fresh()`` (the first part's input written, its state dict returned); one holding
    an interrupted run of the same spec (``spec_dict``, as the state file holds it) resumes
    from its newest readable restart file with ``resume(k, step, restart)``; a finished one
    runs nothing. ``progress(step, total)`` reports the timestep. Shared by the indentation
    and the scratch runs."""
    state_path = run_dir / STATE_FILE
    state = read_json(state_path, "run state") if state_path.exists() else None
    # compared as written: JSON has no NaN or infinity (`to_jsonable` writes them as null)
    if state is not None and to_jsonable(state.get("spec")) != spec_dict:
        raise InputError("the run directory holds a run of a different spec; choose another "
                         f"directory (run directory {run_dir})")
    report = (lambda step: progress(step, total)) if progress is not None else None
    while state is None or not state.get("finished"):
        restarts = restart_files(run_dir) if state is not None else []
        if state is None or not restarts or not (run_dir / SURFACE_FILE).exists():
            state = {"spec": spec_dict, "parts": [fresh()], "finished": False,
                     "engine": engine.to_dict()}
        else:
            step, restart = restarts[0]
            state["parts"].append(resume(len(state["parts"]), step, restart))
        write_json(state_path, state)
        part = state["parts"][-1]
        started = time.perf_counter()
        try:
            run_input(part["input"], run_dir, engine, log_name=f"log.{part['input']}",
                      progress=report)
        except LammpsError as exc:
            if "restart" in part and "restart" in exc.message.lower():
                # a restart file cut short by the interruption: set it aside, use the previous
                (run_dir / part["restart"]).rename(run_dir / f"{part['restart']}.unreadable")
                state["parts"].pop()
                write_json(state_path, state)
                continue
            raise
        part["wall_time"] = time.perf_counter() - started
        state["finished"] = True
        write_json(state_path, state)
        for _, restart in restart_files(run_dir):    # a finished run needs no checkpoints
            restart.unlink()


def run_indentation(spec: IndentSpec, run_dir: Path | str,
                    engine: EngineOptions = EngineOptions(), *,
                    progress: Callable[[int, int], None] | None = None) -> IndentRun:
    """Run ``spec`` in ``run_dir``, or finish it there: a directory holding an interrupted
    run of the same spec resumes from its newest readable restart file; a finished one is
    read back without launching LAMMPS. ``progress(step, total)`` reports the timestep.
    """
    check_made(spec.slab.layers(), "run_indentation")
    run_dir = Path(run_dir).resolve()
    run_dir.mkdir(parents=True, exist_ok=True)
    (run_dir / "dumps").mkdir(exist_ok=True)
    run_resumable(run_dir, _spec_dict(spec), spec.protocol.schedule().s_end,
                  lambda: _fresh(spec, run_dir),
                  lambda k, step, restart: _resume_part(spec, run_dir, k, step, restart),
                  engine, progress)
    return read_run(spec, run_dir)


def stitched_record(run_dir: Path, parts: list[dict], columns: tuple[str, ...]) -> np.ndarray:
    """The rows of the ``fix print`` records of a run's parts (each its own file, from its
    ``start`` step to the next part's), in step order, each step once (fix print repeats a
    row at the first step of each ``run`` that starts on its interval); LammpsError for a
    record whose columns are not ``columns``."""
    rows = []
    for k, part in enumerate(parts):
        found, data = parse_table((run_dir / part["record"]).read_text())
        if found != columns:
            raise LammpsError(f"{part['record']} has columns {found}, expected {columns}",
                              run_dir)
        end = parts[k + 1]["start"] if k + 1 < len(parts) else np.inf
        rows.append(data[(data[:, 0] > part["start"]) & (data[:, 0] <= end)])
    data = np.concatenate(rows)
    data = data[np.argsort(data[:, 0], kind="stable")]
    return data[np.unique(data[:, 0], return_index=True)[1]]


def read_run(spec: IndentSpec, run_dir: Path | str) -> IndentRun:
    """The curve and files of a finished run directory (no LAMMPS)."""
    run_dir = check_path("run_dir", run_dir).resolve()
    state = json.loads((run_dir / STATE_FILE).read_text())
    parts = state["parts"]
    data = stitched_record(run_dir, parts, RECORD_COLUMNS)
    schedule = spec.protocol.schedule()
    steps = data[:, 0].astype(int)
    col = {name: data[:, i] for i, name in enumerate(RECORD_COLUMNS)}
    z_surface = float((run_dir / SURFACE_FILE).read_text().split()[0])
    curve = LoadDisplacementCurve(
        h=lammps_to_si(col["depth"], "length"), P=lammps_to_si(col["load"], "force"),
        t=lammps_to_si(col["time"], "time"), segment=schedule.segment(steps),
        indenter=spec.indenter.tip,
        meta={"source": "filmscale.md atomistic indentation", "name": spec.name,
              "run_dir": str(run_dir), "potential": spec.potential.name,
              "potential_sha256": spec.potential.sha256,
              # the fixed atoms are the rigid base (`continuum.calibration.sphere`'s note)
              "base_depth": float(lammps_to_si(z_surface, "length"))
              - spec.slab.fixed_thickness})
    dumps = tuple(sorted((int(p.stem.split(".")[1]), p)
                         for p in (run_dir / "dumps").glob("indent.*.lammpstrj")))
    return IndentRun(spec=spec, run_dir=run_dir, curve=curve,
                     z_surface=float(lammps_to_si(z_surface, "length")), steps=steps,
                     parts=tuple(parts), dumps=dumps,
                     wall_time=sum(p.get("wall_time", 0.0) for p in parts),
                     engine=state.get("engine", {}))
