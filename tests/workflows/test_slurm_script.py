"""The run-unit task's batch script without SLURM: a fake ``scontrol`` on PATH records its
arguments. Oracle: what SLURM would be asked (``scontrol requeue JOB_TASK`` on USR1, nothing
once the task's requeue count reaches the cap) and the command's own exit status."""

import os
import signal
import subprocess
import sys
import time

import pytest

from filmscale.workflows.slurm import MAX_REQUEUES, task_script


def _start(tmp_path, restarts: int):
    calls = tmp_path / "calls"
    fake = tmp_path / "bin" / "scontrol"
    fake.parent.mkdir()
    fake.write_text(f'#!/bin/sh\necho "$@" >> {calls}\n')
    fake.chmod(0o755)
    # the command: waits for SIGTERM (what SLURM sends a requeued task), then exits 7
    command = [sys.executable, "-c", "import signal, sys, time; signal.signal(signal.SIGTERM, "
               "lambda *a: sys.exit(7)); open(sys.argv[1], 'w').close(); time.sleep(60)",
               str(tmp_path / "started")]
    script = tmp_path / "task.sh"
    script.write_text(task_script(command, requeue_on_timeout=True))
    env = {**os.environ, "PATH": f"{fake.parent}:{os.environ['PATH']}",
           "SLURM_ARRAY_JOB_ID": "41", "SLURM_ARRAY_TASK_ID": "3",
           "SLURM_RESTART_COUNT": str(restarts)}
    shell = subprocess.Popen(["bash", str(script)], env=env)
    deadline = time.time() + 20
    while not (tmp_path / "started").exists():
        assert time.time() < deadline, "the task's command did not start"
        time.sleep(0.05)
    return shell, calls


def _child_of(shell):
    out = subprocess.run(["pgrep", "-P", str(shell.pid)], capture_output=True, text=True)
    return int(out.stdout.split()[0])


@pytest.mark.parametrize("restarts, requeued", [(0, True), (MAX_REQUEUES, False)])
def test_usr1_requeues_the_task_and_the_shell_waits_for_its_command(tmp_path, restarts,
                                                                     requeued):
    shell, calls = _start(tmp_path, restarts)
    child = _child_of(shell)
    shell.send_signal(signal.SIGUSR1)
    time.sleep(1.0)
    assert shell.poll() is None             # the trap ran; the shell still waits
    assert (calls.read_text().split() if calls.exists() else []) == (
        ["requeue", "41_3"] if requeued else [])
    os.kill(child, signal.SIGTERM)          # what SLURM does to a requeued task
    assert shell.wait(timeout=20) == 7      # the command's status, not the trap's


def test_without_requeue_the_script_execs_the_command():
    script = task_script(["filmscale", "sweep", "run", "it's"], requeue_on_timeout=False)
    assert script == "#!/bin/sh\nexec 'filmscale' 'sweep' 'run' 'it'\\''s'\n"


def test_a_time_limit_too_short_to_requeue_is_refused(tmp_path):
    (tmp_path / "sweep.toml").write_text('base = "base.toml"\n')    # refused before it is read
    done = subprocess.run([sys.executable, "-m", "filmscale", "sweep", "submit",
                           str(tmp_path / "sweep.toml"), "--store", str(tmp_path / "s"),
                           "--time", "3"],
                          capture_output=True, text=True)
    assert done.returncode == 2 and "--time = 3 min must exceed 3 min" in done.stderr
    assert "Traceback" not in done.stderr and not (tmp_path / "s").exists()
