"""Progress of long runs on stderr: a bar on a terminal, one line per item in a log, nothing when quiet.

The mode (:func:`progress_mode`):

- ``"bar"``: a tqdm bar, when stderr is a terminal;
- ``"lines"``: when stderr is not a terminal (a log file, CI, ``script``, a pipe), one line per completed item of
  the main counter (a case, a position, a wear step) with its count and the elapsed time in s, e.g.
  ``positions: 3/24 (41.2 s)``; secondary counters (load stages, passes, conditions) stay silent there;
- ``"off"``: with ``quiet=True`` (the commands' ``--quiet``).

``WRLAYER_PROGRESS`` overrides the choice: ``0``/``false``/``no`` off, ``1``/``bar`` bar, ``lines`` lines.
"""

from __future__ import annotations

import os
import sys
import time
from collections.abc import Iterable, Iterator
from typing import TypeVar

T = TypeVar("T")

MODES = ("bar", "lines", "off")


def progress_mode(quiet: bool = False) -> str:
    """"bar", "lines" or "off" (see the module docstring)."""
    if quiet:
        return "off"
    env = os.environ.get("WRLAYER_PROGRESS")
    if env is not None:
        value = env.strip().lower()
        if value in ("0", "", "false", "no", "off"):
            return "off"
        if value in ("lines", "log"):
            return "lines"
        return "bar"
    return "bar" if getattr(sys.stderr, "isatty", lambda: False)() else "lines"


def progress_enabled(quiet: bool = False) -> bool:
    """True when a progress bar is drawn (stderr is a terminal, or ``WRLAYER_PROGRESS=1``)."""
    return progress_mode(quiet) == "bar"


def _line(desc: str, n: int, total: int | None, unit: str, t0: float) -> None:
    count = f"{n}/{total}" if total else f"{n}"
    print(f"{desc}: {count} {unit} ({time.perf_counter() - t0:.1f} s)", file=sys.stderr, flush=True)


def _lines(iterable: Iterable[T], desc: str, total: int | None, unit: str) -> Iterator[T]:
    t0 = time.perf_counter()
    for n, item in enumerate(iterable, start=1):
        yield item
        _line(desc, n, total, unit, t0)


def progress(iterable: Iterable[T], desc: str, total: int | None = None, unit: str = "it",
             quiet: bool = False, lines: bool = True, **kwargs) -> Iterable[T]:
    """``iterable`` with its progress shown in the current mode; ``lines=False`` for a secondary counter (no
    lines in a log). ``kwargs`` go to tqdm."""
    mode = progress_mode(quiet)
    if mode == "lines" and lines:
        if total is None and hasattr(iterable, "__len__"):
            total = len(iterable)  # type: ignore[arg-type]
        return _lines(iterable, desc, total, unit)
    if mode != "bar":
        return iterable
    from tqdm import tqdm  # only when a bar is drawn

    return tqdm(iterable, desc=desc, total=total, unit=unit, file=sys.stderr, dynamic_ncols=True, **kwargs)


class ProgressBar:
    """A counter shown in the current mode; use :meth:`update` from callbacks (e.g. a runner's ``on_progress``)
    and as a context manager. ``lines=False``: a secondary counter, silent in a log."""

    def __init__(self, total: int, desc: str, unit: str = "it", quiet: bool = False, position: int = 0,
                 lines: bool = True, leave: bool = True):
        self.total, self.n = int(total), 0
        self.desc, self.unit = desc, unit
        self._bar = None
        self._t0 = time.perf_counter()
        mode = progress_mode(quiet)
        self._lines = mode == "lines" and lines
        if mode == "bar":
            from tqdm import tqdm  # only when a bar is drawn

            self._bar = tqdm(total=total, desc=desc, unit=unit, file=sys.stderr, dynamic_ncols=True,
                             position=position, leave=leave)

    def update(self, n: int = 1) -> None:
        self.n += n
        if self._bar is not None:
            self._bar.update(n)
        elif self._lines:
            _line(self.desc, self.n, self.total, self.unit, self._t0)

    def reset(self, total: int | None = None) -> None:
        """Start counting again (e.g. the conditions of the next wear step)."""
        self.n = 0
        self.total = self.total if total is None else int(total)
        if self._bar is not None:
            self._bar.reset(total=self.total)

    def grow_total(self, total: int) -> None:
        """Raise the total when more items turn out to be needed (e.g. wear steps cut by the step control)."""
        if total > self.total:
            self.total = int(total)
            if self._bar is not None:
                self._bar.total = self.total
                self._bar.refresh()

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None

    def __enter__(self) -> ProgressBar:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
