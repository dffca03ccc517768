"""Progress bars for long runs (tqdm on stderr), silent where they would only write escape codes into a log.

A bar is shown only when stderr is a terminal (or ``WRLAYER_PROGRESS=1``); ``WRLAYER_PROGRESS=0`` or
``quiet=True`` switches it off. In a log file or CI output a run prints its own one-line summaries instead.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Iterable
from typing import TypeVar

T = TypeVar("T")


def progress_enabled(quiet: bool = False) -> bool:
    """True when a progress bar should be drawn (stderr is a terminal, not quiet, not switched off)."""
    if quiet:
        return False
    env = os.environ.get("WRLAYER_PROGRESS")
    if env is not None:
        return env.strip() not in ("0", "", "false", "no")
    return bool(getattr(sys.stderr, "isatty", lambda: False)())


def progress(iterable: Iterable[T], desc: str, total: int | None = None, unit: str = "it",
             quiet: bool = False, **kwargs) -> Iterable[T]:
    """``iterable`` wrapped in a tqdm bar on stderr when :func:`progress_enabled`, else unchanged."""
    if not progress_enabled(quiet):
        return iterable
    from tqdm import tqdm

    return tqdm(iterable, desc=desc, total=total, unit=unit, file=sys.stderr, dynamic_ncols=True, **kwargs)


class ProgressBar:
    """A counter bar on stderr (tqdm) drawn when :func:`progress_enabled`, else a silent counter; use
    :meth:`update` from callbacks (e.g. a runner's ``on_progress``) and as a context manager."""

    def __init__(self, total: int, desc: str, unit: str = "it", quiet: bool = False, position: int = 0):
        self.total, self.n = int(total), 0
        self._bar = None
        if progress_enabled(quiet):
            from tqdm import tqdm  # only when a bar is drawn

            self._bar = tqdm(total=total, desc=desc, unit=unit, file=sys.stderr, dynamic_ncols=True,
                             position=position)

    def update(self, n: int = 1) -> None:
        self.n += n
        if self._bar is not None:
            self._bar.update(n)

    def close(self) -> None:
        if self._bar is not None:
            self._bar.close()
            self._bar = None

    def __enter__(self) -> ProgressBar:
        return self

    def __exit__(self, *exc) -> None:
        self.close()
