"""Progress of long work on stderr, the one helper every long command uses (`impact-map`,
`indent analyze`, `md indent`, `particles`, `run`): a tqdm bar on a terminal; elsewhere (a
batch job's log file) a plain line every `PLAIN_EVERY_S` seconds, the first and the last
always, with the count, the percentage, the rate and the time left, since a bar redrawn in
place (``\\r``) is unreadable in a file. Both show the time left."""

from __future__ import annotations

import math
import sys
import time

#: seconds between plain progress lines (the first and the last are always written)
PLAIN_EVERY_S = 30.0
#: the terminal bar: the count, the percentage, the elapsed time and the time left
BAR_FORMAT = ("{desc}: {n_fmt}/{total_fmt} {unit} {percentage:3.0f}%|{bar}| "
              "[{elapsed} elapsed, {remaining} left, {rate_fmt}]")


def duration(seconds: float) -> str:
    """``40 s``, ``2.9 min`` or ``1.6 h``."""
    if seconds < 90:
        return f"{seconds:.0f} s"
    if seconds < 90 * 60:
        return f"{seconds / 60:.1f} min"
    return f"{seconds / 3600:.1f} h"


def time_left(seconds: float) -> str:
    """``40 s left``, ``2.9 min left``, ``1.6 h left``, or ``time left unknown``."""
    return f"{duration(seconds)} left" if math.isfinite(seconds) else "time left unknown"


class PlainProgress:
    """The part of tqdm's interface the package uses (``n``, ``total``, ``update``,
    ``close``), written as lines
    ``filmscale: LABEL: 2300/5500 steps, 42% (18.3 steps/s, 2.9 min left)``."""

    def __init__(self, total: int, unit: str, label: str, every: float = PLAIN_EVERY_S,
                 stream=None):
        self.total, self.unit, self.label, self.every = max(int(total), 1), unit, label, every
        self.stream = sys.stderr if stream is None else stream
        self.n = 0
        self._start = self._last = time.monotonic()
        self._said = -1

    def update(self, k: int = 1) -> None:
        self.n = min(self.n + int(k), self.total)
        now = time.monotonic()
        if self.n == self._said:        # nothing new since the last line
            return
        if self._said < 0 or now - self._last >= self.every or self.n == self.total:
            self._line(now)

    def _line(self, now: float) -> None:
        rate = self.n / max(now - self._start, 1e-9)
        left = (self.total - self.n) / rate if rate > 0 else math.inf
        print(f"filmscale: {self.label}: {self.n}/{self.total} {self.unit}s, "
              f"{100 * self.n / self.total:.0f}% ({rate:.3g} {self.unit}s/s, "
              f"{time_left(left)})", file=self.stream, flush=True)
        self._last, self._said = now, self.n

    def close(self) -> None:
        if self._said != self.n:
            self._line(time.monotonic())


def progress_bar(total: int, unit: str, label: str, enabled: bool = True):
    """A tqdm bar when stderr is a terminal, `PlainProgress` lines when it is not, nothing when
    not ``enabled``."""
    from tqdm import tqdm
    if not enabled or sys.stderr.isatty():
        return tqdm(total=total, unit=f"{unit}s", desc=label, disable=not enabled, file=sys.stderr,
                    leave=False, bar_format=BAR_FORMAT)
    return PlainProgress(total, unit, label, every=PLAIN_EVERY_S)


def set_total(bar, total: int) -> None:
    """Give ``bar`` (tqdm or `PlainProgress`) the total once it is better known (the curves of
    files not read yet, the in-range points of a map)."""
    bar.total = max(int(total), 1, bar.n)


def step_callback(bar, total: int):
    """The ``progress(step, total)`` callback of the engines, moving ``bar`` to ``step``."""
    return lambda step, _total: bar.update(max(0, min(step, total) - bar.n))


def with_step_progress(total: int, label: str, work):
    """``work(progress)`` under a bar of ``total`` steps, ``progress`` the engines'
    ``(step, total)`` callback; the bar is closed however the work ends."""
    bar = progress_bar(total, "step", label)
    try:
        return work(step_callback(bar, total))
    finally:
        bar.close()


def count_callback(bar):
    """The ``progress(done, total)`` callback of the maps, moving ``bar`` to ``done`` of the
    ``total`` the map reports (its points, or those in the model's range)."""
    def report(done: int, total: int) -> None:
        if total != bar.total:
            set_total(bar, total)
        bar.update(max(0, min(done, bar.total) - bar.n))
    return report
