"""Sweeps: one base scene and the overrides that make many scenes of it, run locally side by
side on one shared store (units that scenes share are computed once, `workflows.units`).

A sweep file (TOML)::

    base = "demo_scene.toml"          # a pipeline scene, relative to this file
    [axes]                            # every combination of these values
    "impactor.velocity" = [0.5, 1.0, 2.0]
    "target.layers.0.thickness" = [2.2e-9, 5e-9]
    [[cases]]                         # and/or explicit sets of overrides, one scene each
    "impactor.radius" = 1e-6          # (with axes too: each case times every combination)

Keys are dotted paths into the scene; an array of tables is indexed by number (layer 0 is the
top layer). Every scene is checked like a scene file before anything runs.

A swept key that changes nothing the plans keep is reported (`unused_keys`): a layer's
thickness swept while every plan models the substrate alone gives identical results.
"""

from __future__ import annotations

import copy
import itertools
import json
import math
from dataclasses import dataclass
from pathlib import Path

import tomli_w

from filmscale.core.checks import check_keys, check_table, required
from filmscale.core.errors import InputError
from filmscale.core.files import parse_toml, read_text, read_toml
from filmscale.workflows.pipeline_scene import PipelineScene, parse_pipeline

#: more scenes than this from one sweep file is taken for a mistake
MAX_SCENES = 10_000


@dataclass(frozen=True)
class SweepScene:
    """One scene of a sweep: its name, the overrides that made it, the checked scene."""

    name: str
    overrides: dict
    scene: PipelineScene


def _set(data: dict, key: str, value, where: str) -> None:
    """Set the dotted ``key`` in the scene ``data``; its parent must exist."""
    parts = key.split(".")
    node = data
    for i, part in enumerate(parts[:-1]):
        if isinstance(node, list):
            if not part.isdigit() or int(part) >= len(node):
                raise InputError(f"{where}: {key!r}: {'.'.join(parts[:i])} has "
                                 f"{len(node)} entries; {part!r} is not an index of them")
            node = node[int(part)]
        elif isinstance(node, dict) and part in node:
            node = node[part]
        else:
            raise InputError(f"{where}: {key!r}: the base scene has no "
                             f"{'.'.join(parts[:i + 1])}")
    if not isinstance(node, dict):
        raise InputError(f"{where}: {key!r}: {'.'.join(parts[:-1])} is not a table")
    node[parts[-1]] = value


def expand(data: dict, where: str = "sweep") -> list[dict]:
    """The override sets of a sweep's ``axes`` and ``cases`` (see the module docstring)."""
    data = check_keys(where, data, {"base", "name", "axes", "cases"})
    axes = check_table(f"{where}.axes", data.get("axes", {}))
    for key, values in axes.items():
        if not isinstance(values, list) or not values:
            raise InputError(f"{where}.axes.{key} must be a non-empty list of values")
    cases = data.get("cases", [{}])
    if not isinstance(cases, list) or not all(isinstance(c, dict) for c in cases) or not cases:
        raise InputError(f"{where}.cases must be an array of tables ([[cases]])")
    count = len(cases) * math.prod(len(v) for v in axes.values())
    if count > MAX_SCENES:
        raise InputError(f"{where} makes {count} scenes, more than {MAX_SCENES}")
    combos = [dict(zip(axes, values)) for values in itertools.product(*axes.values())]
    return [{**case, **combo} for case in cases for combo in combos]


def parse_sweep(text: str, source: str, base_dir: Path) -> tuple[str, list[SweepScene]]:
    """(the sweep's name, its scenes, each checked), from the sweep file's text."""
    data = parse_toml(text, "sweep", source)
    scene_path = base_dir / str(required("sweep", data, "base"))
    name = str(data.get("name", Path(source).stem))
    base = read_toml(scene_path, "base scene")
    scenes = []
    for i, overrides in enumerate(expand(data, f"sweep {source}")):
        scene_data = copy.deepcopy(base)
        for key, value in overrides.items():
            _set(scene_data, key, value, f"sweep {source}")
        scene_name = f"{name}-{i:03d}"
        scenes.append(SweepScene(scene_name, overrides, parse_pipeline(
            tomli_w.dumps(scene_data), f"{source}:{scene_name}", scene_path.parent)))
    return name, scenes


def load_sweep(path) -> tuple[str, list[SweepScene]]:
    path = Path(path)
    return parse_sweep(read_text(path, "sweep"), str(path), path.parent)


def unused_keys(scenes: list[SweepScene], decisions: list[dict]) -> list[dict]:
    """The swept keys that change nothing the plans keep. ``decisions``: each scene's plan
    decisions ({} while its calibrations have not run). The rule: a key is reported when two
    scenes whose overrides differ in that key's value and in nothing else both have plans
    that leave the key out (`plan.left_out`: a film's key where the plan models the
    substrate alone, the friction of a normal approach); their impact results are then
    identical. Each entry: ``key``, ``cases`` (the scenes of such pairs), ``why``,
    ``keep`` (how to make the key count) and ``text`` (one line)."""
    from filmscale.workflows.plan import left_out
    found = []
    for key in dict.fromkeys(k for s in scenes for k in s.overrides):
        groups: dict[str, list] = {}
        for s, d in zip(scenes, decisions):
            if key in s.overrides and left_out(key, d or {}, s.scene.angle) is not None:
                rest = {k: v for k, v in s.overrides.items() if k != key}
                groups.setdefault(json.dumps(rest, sort_keys=True, default=str),
                                  []).append((s, d))
        pairs = {s.name: d for group in groups.values()
                 if len({json.dumps(s.overrides[key], default=str) for s, _ in group}) > 1
                 for s, d in group}
        if pairs:
            names = [s.name for s in scenes if s.name in pairs]
            first = next(s for s in scenes if s.name == names[0])
            rule, why, keep = left_out(key, pairs[names[0]], first.scene.angle)
            changes = [d["films_change"] for d in pairs.values()
                       if d.get("films_change") is not None]
            if rule == 3 and changes:
                why += f" ({max(changes):.2%} at most in these scenes)"
            shown = ", ".join(names[:6]) + (f" and {len(names) - 6} more" if len(names) > 6
                                            else "")
            found.append({"key": key, "cases": names, "why": why, "keep": keep, "text": (
                f"{key} changes nothing the plan keeps in {len(names)} of {len(scenes)} "
                f"scene(s) ({shown}): {why}, so its value does not reach their impact results "
                f"(those that differ in it alone are identical); to keep it, {keep}")})
    return found


def _run_one(job) -> dict:
    """Run one scene of a sweep (in a worker process): its result path and units, or the
    one-line error that stopped it."""
    from filmscale.core.errors import FilmscaleError
    from filmscale.workflows.pipeline import run_scene
    text, source, base, store, out = job
    try:
        result = run_scene(parse_pipeline(text, source, Path(base)), Path(store), Path(out))
    except FilmscaleError as err:
        return {"error": str(err)}
    return {"result": str(result.path), "units": result.units,
            "decisions": result.plan.decisions}


def default_jobs(scenes: list[SweepScene]) -> int:
    """Scenes run at once: the CPUs this process may use over the ranks one scene's runs
    take (its largest `np`), at least 1."""
    from filmscale.core.cores import usable_cores
    ranks = max((src.np for s in scenes for src in s.scene.calibrations), default=1)
    return max(1, usable_cores() // ranks)


def run_sweep(name: str, scenes: list[SweepScene], store: Path, out_dir: Path,
              jobs: int | None = None, say=print, index_name: str | None = None
              ) -> tuple[Path, list[dict]]:
    """Run every scene on the shared ``store`` (``jobs`` at a time, `default_jobs` when None),
    each result as ``out_dir/<scene>.h5``; the index ``out_dir/<name>.json`` (each scene's
    overrides, result or error, units) is rewritten as each scene ends, so that a stopped
    sweep keeps what finished (``index_name`` names it otherwise: the tasks of a SLURM array,
    one scene each, write one index each). When every scene has ended, the index gets
    ``warnings``: the swept keys that change nothing the finished scenes' plans keep
    (`unused_keys`), each also said in one line. Returns the index path and its entries."""
    from concurrent.futures import ProcessPoolExecutor, as_completed

    from filmscale.core.files import write_json
    out_dir.mkdir(parents=True, exist_ok=True)
    jobs = default_jobs(scenes) if jobs is None else max(1, int(jobs))
    index = out_dir / (index_name or f"{name}.json")
    entries = [{"name": s.name, "overrides": s.overrides, "state": "pending"} for s in scenes]
    work = [(s.scene.text, s.scene.source, str(s.scene.base), str(store),
             str(out_dir / f"{s.name}.h5")) for s in scenes]
    write_json(index, {"sweep": name, "scenes": entries})

    def record(i: int, outcome: dict) -> None:
        entries[i].update(outcome, state="failed" if "error" in outcome else "done")
        write_json(index, {"sweep": name, "scenes": entries})
        say(f"{scenes[i].name}: " + (f"failed: {outcome['error']}" if "error" in outcome
                                     else f"done, {outcome['result']}"))
    if jobs == 1:
        for i, job in enumerate(work):
            record(i, _run_one(job))
    else:
        with ProcessPoolExecutor(jobs) as pool:
            futures = {pool.submit(_run_one, job): i for i, job in enumerate(work)}
            for future in as_completed(futures):
                record(futures[future], future.result())
    warnings = unused_keys(scenes, [e.get("decisions", {}) for e in entries])
    write_json(index, {"sweep": name, "scenes": entries, "warnings": warnings})
    for w in warnings:
        say(f"warning: {w['text']}")
    return index, entries
