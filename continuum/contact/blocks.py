"""The fast paths' point blocks: points solved in blocks of `BLOCK` on a thread pool.

Blocks keep the (points x pieces x nodes) temporaries of a fast path in memory that is
reused; each block writes its own entries of the result arrays, and numpy releases the GIL
in its array loops, so threads share the cores. OpenBLAS's own threads, started by every
small matrix product inside a block (the layered profiles), would fight the workers for the
cores (a layered map took as long on 2 threads as on 1), so they are held to one.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from contextlib import nullcontext

import numpy as np
from threadpoolctl import threadpool_limits

from filmscale.core.cores import usable_cores

#: points solved together: temporaries of a few MB
BLOCK = 1024


def solve_in_blocks(points: np.ndarray, solve, progress=None) -> None:
    """``solve(block)`` on each block of the index array ``points``, in threads when there
    are several blocks; ``progress(done, total)`` after each block."""
    blocks = np.array_split(points, -(-points.size // BLOCK)) if points.size else []
    workers = min(len(blocks), usable_cores())
    done = 0
    with (ThreadPoolExecutor(workers) if workers > 1 else nullcontext()) as pool, \
            (threadpool_limits(1, user_api="blas") if workers > 1 else nullcontext()):
        for block in (pool.map if pool else map)(lambda b: (solve(b), b)[1], blocks):
            done += block.size
            if progress is not None:
                progress(done, points.size)
