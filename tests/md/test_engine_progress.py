"""The log follower behind the progress bars: it reports thermo steps only.

A LAMMPS log has other lines that start with a number ("32856 atoms in group target",
"  1 by 2 by 1 MPI processor grid"); taken as steps they sent a particle run's bar to 100 %
before its first timestep (seen with a 32 856-particle block against 8 033 estimated steps).
"""

from filmscale.md.engine import _LogFollower

PREAMBLE = """LAMMPS (22 Jul 2025 - Update 4)
  1 by 2 by 1 MPI processor grid
Created 32856 atoms
32856 atoms in group target
  32856 settings made for mol
888 atoms in group on_x
"""
THERMO = """   Step           Dt            v_t          v_depth         v_load
         0   1e-16          0              0              0
       160   0.0033118538   0.98981554     0.029694466    0.016891585
WARNING: a warning in the middle of a block (src/fix.cpp:1)
       320   0.0033118538   0.98981554     0.029694466    0.016891585
"""
END = """Loop time of 12.5 on 2 procs for 320 steps with 32856 atoms
  32856 atoms in group still counted after the run
Total wall time: 0:00:13
"""


def test_follower_reports_thermo_steps_and_nothing_else(tmp_path):
    log = tmp_path / "log.in.tlsph"
    seen = []
    follower = _LogFollower(log, seen.append)
    follower.poll()                          # no log yet: nothing
    log.write_text(PREAMBLE)
    follower.poll()
    assert seen == []
    with log.open("a") as f:
        f.write(THERMO)
    follower.poll()
    with log.open("a") as f:
        f.write(END)
    follower.poll()
    assert seen == [320]                     # the last step of the chunk; the warning skipped
    assert max(seen) <= 320


def test_follower_keeps_partial_lines_for_the_next_read(tmp_path):
    log = tmp_path / "log"
    seen = []
    follower = _LogFollower(log, seen.append)
    text = PREAMBLE + THERMO
    cut = text.index("160") + 2              # a thermo line split mid-number
    log.write_text(text[:cut])
    follower.poll()
    assert seen == [0]
    with log.open("a") as f:
        f.write(text[cut:])
    follower.poll()
    assert seen == [0, 320]
