"""Start-up and whole-command times of the `filmscale` command line.

Run:  .venv/bin/python benchmarks/startup.py [--repeat 5]

Each command runs as a fresh process (`python -m filmscale ...`, the interpreter running this
script); the table gives the best wall time of --repeat runs (the best, because other load on
the machine only ever adds time), its ratio to `python -c "import numpy"` measured the same
way, the target and whether it holds. The targets are issue 21's: `--help` within 3 x the
numpy import, a 100 x 100 `impact-map` of examples/slider_corner_disk.toml (HDF5 written) in
under 1 s as a whole command; `impact` is held to the same second. Exit status 1 when a target
fails.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCENE = ROOT / "examples" / "slider_corner_disk.toml"


def best_time(argv: list[str], repeat: int) -> float:
    """The shortest wall time (s) of ``repeat`` runs of ``argv``; a failed run stops."""
    # bytecode caches written, as an installed package has them: the first run (not timed)
    # writes them; a shell with PYTHONDONTWRITEBYTECODE would otherwise compile every time
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    times = []
    for _ in range(repeat + 1):
        start = time.perf_counter()
        done = subprocess.run(argv, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True,
                              env=env)
        times.append(time.perf_counter() - start)
        if done.returncode != 0:
            sys.exit(f"{' '.join(argv)} failed ({done.returncode}): {done.stderr.strip()}")
    return min(times[1:])


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="runs per command (default 5)")
    args = parser.parse_args()
    python = sys.executable
    cli = [python, "-m", "filmscale"]
    with tempfile.TemporaryDirectory() as tmp:
        out = str(Path(tmp) / "map.h5")
        # (label, argv, target: ("ratio", x) to the numpy import or ("seconds", s))
        cases = [
            ("filmscale --help", [*cli, "--help"], ("ratio", 3.0)),
            ("filmscale impact SCENE", [*cli, "impact", str(SCENE)], ("seconds", 1.0)),
            ("filmscale impact-map SCENE (100 x 100)",
             [*cli, "impact-map", str(SCENE), "--velocity", "0.001:2:100",
              "--radius", "1e-6:50e-6:100", "--out", out, "--force"], ("seconds", 1.0)),
        ]
        reference = best_time([python, "-c", "import numpy"], args.repeat)
        rows = [("python -c 'import numpy'", reference, "reference", True)]
        for label, argv, (kind, limit) in cases:
            seconds = best_time(argv, args.repeat)
            if kind == "ratio":
                target, ok = f"<= {limit:g} x numpy", seconds <= limit * reference
            else:
                target, ok = f"< {limit:g} s", seconds < limit
            rows.append((label, seconds, target, ok))
    width = max(len(r[0]) for r in rows)
    print(f"best of {args.repeat} runs, {python}")
    print(f"{'command':<{width}}  {'best [s]':>8}  {'x numpy':>7}  {'target':<16}  result")
    for label, seconds, target, ok in rows:
        print(f"{label:<{width}}  {seconds:8.3f}  {seconds / reference:7.2f}  {target:<16}  "
              f"{'pass' if ok else 'FAIL'}")
    return 0 if all(r[3] for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
