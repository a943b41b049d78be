"""A recorded-output fake of the MD engine (no LAMMPS): what LAMMPS wrote in the ci preset's
run, kept under tests/md/recorded/ci."""

import shutil
from pathlib import Path

#: the recorded ci run
RECORDED = Path(__file__).resolve().parents[1] / "md" / "recorded" / "ci"


class RecordedEngine:
    """Stands in for `run_input`: copies what LAMMPS wrote in the recorded ci run."""

    def __init__(self, stop_after_step=None):
        self.calls = []
        self.stop_after_step = stop_after_step

    def __call__(self, input_file, run_dir, options, *, log_name, progress=None):
        run_dir = Path(run_dir)
        self.calls.append((input_file, (run_dir / input_file).read_text()))
        shutil.copy(RECORDED / "surface_z.txt", run_dir)
        shutil.copytree(RECORDED / "dumps", run_dir / "dumps", dirs_exist_ok=True)
        lines = (RECORDED / "indent.dat").read_text().splitlines()
        header, rows = lines[0], lines[1:]
        if input_file == "in.indent":
            record = "indent.dat"
            if self.stop_after_step is not None:
                rows = [r for r in rows if int(r.split()[0]) <= self.stop_after_step]
                (run_dir / "restart.600.bin").write_bytes(b"recorded")
                (run_dir / record).write_text("\n".join([header, *rows]) + "\n")
                raise KeyboardInterrupt
        else:
            record = "indent.1.dat"
            # the resumed part: rows from its restart step on, loads shifted by 1 eV/A so
            # that the merge can be told apart
            rows = [" ".join(w if i != 4 else repr(float(w) + 1.0)
                             for i, w in enumerate(r.split()))
                    for r in rows if int(r.split()[0]) >= 600]
        (run_dir / record).write_text("\n".join([header, *rows]) + "\n")
        (run_dir / log_name).write_text((RECORDED / "log.in.indent").read_text())
        return (RECORDED / "log.in.indent").read_text()
