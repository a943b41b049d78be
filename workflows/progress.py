"""Progress of long work on stderr: a tqdm bar on a terminal; elsewhere (a batch job's log
file) a plain line every `PLAIN_EVERY_S` seconds with the percentage, the rate and the time
left, since a bar redrawn in place is unreadable in a file."""

from __future__ import annotations

import sys
import time

#: seconds between plain progress lines (the first and the last are always written)
PLAIN_EVERY_S = 30.0


class PlainProgress:
    """The part of tqdm's interface the package uses (``n``, ``update``, ``close``), written as
    lines ``filmscale: LABEL 42% (2300/5500 steps, 18.3 steps/s, 2.9 min left)``."""

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
        if self._said < 0 or now - self._last >= self.every or self.n == self.total:
            self._line(now)

    def _line(self, now: float) -> None:
        rate = self.n / max(now - self._start, 1e-9)
        left = (self.total - self.n) / rate if rate > 0 else float("inf")
        eta = f"{left / 60:.1f} min left" if left != float("inf") else "time left unknown"
        print(f"filmscale: {self.label} {100 * self.n / self.total:.0f}% ({self.n}/{self.total} "
              f"{self.unit}s, {rate:.3g} {self.unit}s/s, {eta})", file=self.stream, flush=True)
        self._last, self._said = now, self.n

    def close(self) -> None:
        if self._said != self.n:
            self._line(time.monotonic())


def progress_bar(total: int, unit: str, label: str, enabled: bool = True):
    """A tqdm bar when stderr is a terminal, `PlainProgress` lines when it is not, nothing when
    not ``enabled``."""
    from tqdm import tqdm
    if not enabled or sys.stderr.isatty():
        return tqdm(total=total, unit=unit, desc=label, disable=not enabled, file=sys.stderr,
                    leave=False)
    return PlainProgress(total, unit, label)


def step_callback(bar, total: int):
    """The ``progress(step, total)`` callback of the engines, moving ``bar`` to ``step``."""
    return lambda step, _total: bar.update(max(0, min(step, total) - bar.n))
