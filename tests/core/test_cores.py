"""usable_cores follows the process's affinity mask (a SLURM step's or a cgroup's cpuset), not
the machine's CPU count. Oracle: the mask the test sets."""

import os

import pytest

from filmscale.core.cores import usable_cores


@pytest.mark.skipif(not hasattr(os, "sched_setaffinity"), reason="no affinity masks here")
def test_usable_cores_is_the_affinity_mask():
    mask = os.sched_getaffinity(0)
    try:
        os.sched_setaffinity(0, {min(mask)})
        assert usable_cores() == 1
    finally:
        os.sched_setaffinity(0, mask)
    assert usable_cores() == len(mask) <= (os.cpu_count() or len(mask))
