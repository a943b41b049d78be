"""How many CPUs this process may use."""

from __future__ import annotations

import os


def usable_cores() -> int:
    """The CPUs in this process's affinity mask (what a SLURM job step, a cgroup cpuset or
    taskset allows), not the machine's count; the machine's where the mask is not available."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:          # not Linux
        return os.cpu_count() or 1
