"""Progress in a log file: plain lines with the count, percentage, rate and time left, the
first and the last always, the others no more often than asked, nothing said twice; the
terminal bar's total corrected as it becomes known. Oracle: the counts fed in."""

import io
import math

import pytest

from filmscale.workflows.progress import (PlainProgress, count_callback, progress_bar,
                                          set_total, step_callback, time_left)


def test_plain_lines_give_the_share_done_and_end_at_100_percent():
    out = io.StringIO()
    bar = PlainProgress(200, "step", "md-indent-x (MD)", every=3600.0, stream=out)
    callback = step_callback(bar, 200)
    for step in (10, 50, 120, 250, 260):      # an engine may report past the end: clipped
        callback(step, 200)
    bar.close()
    lines = out.getvalue().splitlines()
    # the first report and the last (100 %) only: the hour between lines never passed, and
    # the report past the end and close() repeat nothing
    assert len(lines) == 2
    assert lines[0].startswith("filmscale: md-indent-x (MD): 10/200 steps, 5% (")
    assert lines[1].startswith("filmscale: md-indent-x (MD): 200/200 steps, 100% (")
    assert lines[0].endswith(" left)") and lines[1].endswith(" steps/s, 0 s left)")


def test_every_update_is_a_line_when_asked_and_close_adds_the_last():
    out = io.StringIO()
    bar = PlainProgress(4, "curve", "analysing", every=0.0, stream=out)
    bar.update(1)
    bar.update(2)
    bar.update(0)                           # nothing new: no line
    bar.close()
    # one line per update; close() repeats nothing already said
    assert [line.split(": ")[2].split(",")[0] for line in out.getvalue().splitlines()] == \
        ["1/4 curves", "3/4 curves"]


@pytest.mark.parametrize("seconds, text", [
    (0.2, "0 s left"), (40.4, "40 s left"), (89.0, "89 s left"), (174.0, "2.9 min left"),
    (5340.0, "89.0 min left"), (5760.0, "1.6 h left"), (math.inf, "time left unknown")])
def test_time_left_in_seconds_minutes_or_hours(seconds, text):
    assert time_left(seconds) == text


def test_a_log_file_gets_plain_lines(capsys):
    """stderr is not a terminal under pytest's capture: the plain reporter is chosen."""
    bar = progress_bar(10, "step", "run")
    assert isinstance(bar, PlainProgress)
    bar.update(10)
    bar.close()
    assert "filmscale: run: 10/10 steps, 100% (" in capsys.readouterr().err
    assert not isinstance(progress_bar(10, "step", "off", enabled=False), PlainProgress)


def test_a_map_reports_its_own_total():
    """A map's ``progress(done, total)``: the total it reports (the points in the model's
    range) replaces the one the bar started with; never below what is done."""
    out = io.StringIO()
    bar = PlainProgress(9, "impact", "glass only", every=0.0, stream=out)
    report = count_callback(bar)
    report(2, 6)
    report(6, 6)
    assert out.getvalue().splitlines()[-1].startswith("filmscale: glass only: 6/6 impacts, "
                                                      "100% (")
    set_total(bar, 3)
    assert bar.total == 6
