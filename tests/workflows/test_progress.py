"""Progress in a log file: plain lines with percentage, rate and time left, the first and the
last always, the others no more often than asked. Oracle: the counts fed in."""

import io

from filmscale.workflows.progress import PlainProgress, progress_bar, step_callback


def test_plain_lines_give_the_share_done_and_end_at_100_percent():
    out = io.StringIO()
    bar = PlainProgress(200, "step", "md-indent-x (MD)", every=3600.0, stream=out)
    callback = step_callback(bar, 200)
    for step in (10, 50, 120, 250):      # an engine may report past the end: clipped
        callback(step, 200)
    bar.close()
    lines = out.getvalue().splitlines()
    # the first report and the last (100 %) only: the hour between lines never passed
    assert len(lines) == 2
    assert lines[0].startswith("filmscale: md-indent-x (MD) 5% (10/200 steps, ")
    assert lines[1].startswith("filmscale: md-indent-x (MD) 100% (200/200 steps, ")
    assert "min left" in lines[0]


def test_every_update_is_a_line_when_asked_and_close_adds_the_last():
    out = io.StringIO()
    bar = PlainProgress(4, "curve", "analysing", every=0.0, stream=out)
    bar.update(1)
    bar.update(2)
    bar.close()
    # one line per update; close() repeats nothing already said
    assert [line.split("(")[1].split(",")[0] for line in out.getvalue().splitlines()] == \
        ["1/4 curves", "3/4 curves"]


def test_a_log_file_gets_plain_lines(capsys):
    """stderr is not a terminal under pytest's capture: the plain reporter is chosen."""
    bar = progress_bar(10, "step", "run")
    assert isinstance(bar, PlainProgress)
    bar.update(10)
    bar.close()
    assert "filmscale: run 100% (10/10 steps" in capsys.readouterr().err
    assert not isinstance(progress_bar(10, "step", "off", enabled=False), PlainProgress)
