"""Choice of the normal contact solver: ``method.normal`` of every scene (units mm, N, MPa).

    "kik_piotrowski"  the paper's fast method (default), :func:`contact.normal.kik_piotrowski.solve_normal`
    "exact"           the FFT boundary-element half-space solver with the same layer, cell by cell,
                      :func:`contact.normal.exact.solve_exact` (options ``method.exact_cells``, ``method.layer_mode``)

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
    """``method.normal`` and its options. ``exact_cells``: cells along x over the patch length of the exact
    solver's grid (None: :data:`contact.normal.exact.DEFAULT_CELLS`); ``layer_mode``: "indentation" or "rolling"
    (exact solver only; see :mod:`contact.normal.exact_layer`)."""

    name: str = "kik_piotrowski"
    exact_cells: int | None = None
    layer_mode: str = "indentation"

    def __post_init__(self):
        if self.name not in NORMAL_METHODS:
            raise InputError("method.normal", f"must be one of {', '.join(NORMAL_METHODS)}, got {self.name!r}")
        self.exact_options()                                  # validates exact_cells and layer_mode

    def exact_options(self, **overrides):
        """The :class:`contact.normal.exact.ExactOptions` of this choice (InputError naming the key if invalid)."""
        from contact.normal.exact import DEFAULT_CELLS, ExactOptions

        cells = DEFAULT_CELLS if self.exact_cells is None else self.exact_cells
        return ExactOptions(cells=cells, layer_mode=self.layer_mode, **overrides)


def solve_normal_with(method: NormalMethod, prob: NormalProblem, layer: LayerPair | None = None,
                      **kwargs) -> NormalSolution:
    """Solve the normal problem with the chosen method (keyword arguments as :func:`solve_normal`)."""
    if method.name == "kik_piotrowski":
        return solve_normal(prob, layer, **kwargs)
    from contact.normal.exact import solve_exact

    return solve_exact(prob, layer, method.exact_options(), **kwargs)
