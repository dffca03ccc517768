"""Cost guards: the work a run asks for is estimated BEFORE it starts; above a limit the run is refused with the
estimate (an :class:`~wrlayer.errors.InputError`, exit code 2), unless the user forces it (``--force``).

An estimate is a product of factors (cases × wheels × passes × strips × cells for contact, positions × FEM size
for calibration) converted to seconds with per-unit times measured on the project's 2-core machine (see
docs/inputs-and-errors.md; the estimate is meant to be right within a factor of a few, which is enough to tell
a 10 s run from a 10 h one). Units: s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from wrlayer.errors import InputError

#: Estimated run time above which a run is refused unless forced (s).
LIMIT_SECONDS = 3600.0


class CostError(InputError):
    """A run refused up front because its estimated cost exceeds the limit (exit code 2, like bad input)."""


def _human(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.3g} s"
    if seconds < 7200:
        return f"{seconds / 60:.3g} min"
    if seconds < 2 * 86400:
        return f"{seconds / 3600:.3g} h"
    return f"{seconds / 86400:.3g} days"


@dataclass(frozen=True)
class CostEstimate:
    """``factors``: named counts whose product is the work (e.g. {"cases": 21, "passes": 60}); ``seconds``: the
    estimated wall time (s); ``what``: the input the run comes from (named in the refusal); ``note``: said after
    the factors (e.g. "on 2 workers")."""

    what: str
    factors: dict[str, float] = field(default_factory=dict)
    seconds: float = 0.0
    note: str = ""

    def describe(self) -> str:
        """``"21 cases x 60 passes x 160 strips ~ 2.1 s"``."""
        parts = " x ".join(f"{_count(v)} {k}" for k, v in self.factors.items())
        return f"{parts}{' ' + self.note if self.note else ''} ~ {_human(self.seconds)}"


def _count(v: float) -> str:
    return f"{int(v)}" if float(v).is_integer() and abs(v) < 1e6 else f"{v:.3g}"


def guard(estimate: CostEstimate, force: bool = False, limit_s: float = LIMIT_SECONDS) -> CostEstimate:
    """Refuse (CostError naming the input and the estimate) when the estimate exceeds ``limit_s`` and the run is
    not forced; returns the estimate otherwise."""
    if not force and not (math.isfinite(estimate.seconds) and estimate.seconds <= limit_s):
        raise CostError(estimate.what, f"estimated cost {estimate.describe()} exceeds the limit of "
                                       f"{_human(limit_s)}: reduce it, or pass --force to run it anyway")
    return estimate


__all__ = ["LIMIT_SECONDS", "CostError", "CostEstimate", "guard"]
