"""Choice of the normal contact solver: ``method.normal`` of every scene (units mm, N, MPa).

    "kik_piotrowski"  the paper's fast method (default), :func:`contact.normal.kik_piotrowski.solve_normal`
    "exact"           the FFT boundary-element half-space solver with the same layer (issue: exact solver)

:func:`solve_normal_with` has the signature of ``solve_normal`` plus the method, and returns a
:class:`~contact.normal.kik_piotrowski.NormalSolution` either way, so passes, FASTSIM, pictures, tables and
wheel-rail scenes work with both.
"""

from __future__ import annotations

from dataclasses import dataclass

from contact.layer.prandtl_layer import LayerPair
from contact.normal.kik_piotrowski import NormalProblem, NormalSolution, solve_normal
from wrlayer.errors import InputError

NORMAL_METHODS = ("kik_piotrowski", "exact")


@dataclass(frozen=True)
class NormalMethod:
    """``method.normal`` and its options. ``exact_cells``: cells along the longer side of the exact solver's grid
    (None: the default of the exact solver); ``layer_mode``: "indentation" or "rolling" (exact solver only)."""

    name: str = "kik_piotrowski"
    exact_cells: int | None = None
    layer_mode: str = "indentation"

    def __post_init__(self):
        if self.name not in NORMAL_METHODS:
            raise InputError("method.normal", f"must be one of {', '.join(NORMAL_METHODS)}, got {self.name!r}")


def solve_normal_with(method: NormalMethod, prob: NormalProblem, layer: LayerPair | None = None,
                      **kwargs) -> NormalSolution:
    """Solve the normal problem with the chosen method (keyword arguments as :func:`solve_normal`)."""
    if method.name == "kik_piotrowski":
        return solve_normal(prob, layer, **kwargs)
    raise InputError("method.normal", "'exact' is not available in this build yet")
