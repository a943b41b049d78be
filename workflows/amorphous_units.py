"""Amorphous blocks as store units: `amorphous_unit` makes (or reuses) the block of a
melt-quench recipe in ``STORE/md-amorphous-<hash>`` (the hash over the recipe and the code
version, `workflows.store`), and `with_blocks` gives an indentation or scratch spec whose films
named by a recipe (`md.amorphous_film.AmorphousLayer.named_by`) carry their made blocks. One
recipe is quenched once per store, whichever command or scene names it; two processes
that name it at once share it (the unit's lock)."""

from __future__ import annotations

import dataclasses
import sys
from pathlib import Path

from filmscale.core.provenance import provenance
from filmscale.workflows.progress import duration, with_step_progress
from filmscale.workflows.store import done_record, finish_unit, own_folder, unit_dir, unit_lock


#: melt-quench throughput of carbon with Tersoff (the ci recipe's melt and quench, 512 atoms,
#: one core: docs/amorphous.md), atom-steps per second per rank
QUENCH_ATOM_STEPS_PER_RANK_S = 4.9e5


def quench_cost_s(recipe, ranks: int) -> float:
    """Estimated wall time (s) of a melt-quench on ``ranks`` ranks: its MD steps and the
    final stage's thirteen relaxations (`md.amorphous`), at the ci rate."""
    from filmscale.md.amorphous import RELAX_STEPS
    steps = recipe.schedule().total + 13 * RELAX_STEPS
    return recipe.n_atoms * steps / (QUENCH_ATOM_STEPS_PER_RANK_S * ranks)


def amorphous_unit(recipe, store: Path, engine, *, quiet: bool = False) -> tuple[Path, bool]:
    """The unit of ``recipe`` in ``store`` and whether it was reused: made (LAMMPS, with a
    progress bar unless ``quiet``) when it is not done yet."""
    from filmscale.md.amorphous_run import (RECORD_NAME, analyze_amorphous, run_amorphous,
                                            write_amorphous_record)
    unit = unit_dir(store, "md-amorphous", recipe.to_dict())
    with unit_lock(unit):
        reused = done_record(unit) is not None
        if not reused:
            total = recipe.schedule().total
            if not quiet:
                cost = quench_cost_s(recipe, engine.np)
                print(f"{recipe.name} (seed {recipe.seed}): {recipe.n_atoms} atoms, {total} "
                      f"steps, {engine.np} rank(s), about {duration(cost)} by the cost "
                      f"model; unit {unit}", file=sys.stderr)
            run = with_step_progress(total, recipe.name, lambda progress: run_amorphous(
                recipe, own_folder(unit), engine, progress=progress))
            write_amorphous_record(run, analyze_amorphous(run), provenance=provenance(
                command="filmscale " + " ".join(sys.argv[1:])))
            finish_unit(unit, {"kind": "md-amorphous", "wall_time": run.wall_time},
                        files=(RECORD_NAME,))
    return unit, reused


def with_blocks(spec, store: Path, engine, *, quiet: bool = False):
    """``spec`` (an `IndentSpec` or a `ScratchSpec`) with each film named by a recipe cut
    from its block, made in (or reused from) ``store``; ``spec`` itself when none is."""
    from filmscale.md.amorphous_film import AmorphousLayer
    from filmscale.md.amorphous_run import read_block
    indent = getattr(spec, "indent", spec)
    films, named = list(indent.slab.films), False
    for k, film in enumerate(films):
        if isinstance(film, AmorphousLayer) and film.block.stand_in:
            unit, _ = amorphous_unit(film.recipe, store, engine, quiet=quiet)
            films[k], named = dataclasses.replace(film, block=read_block(unit)), True
    if not named:
        return spec
    made = dataclasses.replace(indent, slab=dataclasses.replace(indent.slab, films=films),
                               slab_built=None)
    if indent is spec:
        return made
    from filmscale.md.scratch import scratch_of
    return scratch_of(made, spec.stroke, spec.length_x)
