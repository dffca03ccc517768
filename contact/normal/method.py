"""Choice of the normal contact solver: ``method.normal`` of every scene (units mm, N, MPa).

    "auto"            the default of every scene and call that names no method: the accurate solver, resolved once
                      by :func:`resolve_normal_name` (today "exact" in either layer mode, and why not "coarse_exact")
    "kik_piotrowski"  the paper's fast method, :func:`contact.normal.kik_piotrowski.solve_normal`; its p_max is
                      approximate (6-25 % off the exact solution on non-Hertzian patches, up to 50 % on flat-topped
                      ones: docs/validation/fast-normal.md), so a result made with it says so
                      (:attr:`NormalMethod.p_max_approximate`)
    "exact"           the FFT boundary-element half-space solver with the same layer, cell by cell,
                      :func:`contact.normal.exact.solve_exact` (options ``method.exact_cells``, ``method.layer_mode``)
    "coarse_exact"    the same half-space problem on a coarse grid fitted to the patch (indentation layer only),
                      :func:`contact.normal.coarse_exact.solve_coarse_exact`: within 5 % of the converged exact
                      solution on p_max, area, approach and load centre on the benchmark set, at less than half the
                      exact solver's time, but not smooth in its inputs (:func:`resolve_normal_name`)

:func:`solve_normal_with` takes the arguments of ``solve_normal`` (problem, then layer) plus the method as a
keyword, and returns a :class:`~contact.normal.solution.NormalSolution` either way, so passes, FASTSIM, pictures,
tables and wheel-rail scenes work with both.
"""

from __future__ import annotations

from dataclasses import dataclass

from contact.layer.prandtl_layer import LayerPair
from contact.normal.kik_piotrowski import check_arguments, solve_normal
from contact.normal.problem import NormalProblem
from contact.normal.solution import NormalSolution
from wrlayer.errors import InputError

NORMAL_METHODS = ("kik_piotrowski", "exact", "coarse_exact")
#: ``method.normal`` when none is named: resolved by :func:`resolve_normal_name`.
AUTO = "auto"
#: The accepted values of ``method.normal``.
NORMAL_CHOICES = (AUTO, *NORMAL_METHODS)
#: The methods whose p_max is approximate (a result made with one says so: contact.result_warnings).
P_MAX_APPROXIMATE = ("kik_piotrowski",)


def resolve_normal_name(name: str, layer_mode: str) -> str:
    """The normal solver that ``method.normal = name`` runs: ``name`` itself, or for "auto" (the default) the
    accurate solver: "exact" in either layer mode.

    Why not "coarse_exact", within 1.4 % (p_max) and 3.4 % (area) of the converged exact solution on the 30-patch
    benchmark set at less than half the exact solver's time: its grid is refitted to the patch, and a refit moves
    its solution by up to 11 % (patch length) and 9 % (p_max) between nearly equal inputs, so fixed points over
    solutions do not settle (``scale_to_patch`` in 1 of the 21 cases of the shipped layered sweep) and a 60-pass
    history on dents jumps by up to 9 % where the exact solver decreases smoothly (docs/validation/fast-normal.md).
    ``layer_mode`` stays an argument: the resolution may depend on it ("coarse_exact" has no "rolling" mode)."""
    if name != AUTO:
        return name
    return "exact"


@dataclass(frozen=True)
class NormalMethod:
    """``method.normal`` of a scene and its options.

    Attributes
    ----------
    name : str
        The normal solver: "kik_piotrowski" (the paper's fast method, eqs. 9-15), "exact" (FFT half-space) or
        "coarse_exact" (the half-space on a coarse grid); "auto" (the default) is resolved on construction
        (:func:`resolve_normal_name`), so ``name`` is always the solver that runs.
    exact_cells : int or None
        Cells along x over the patch length of the exact solver's grid (1); None:
        :data:`contact.normal.exact.DEFAULT_CELLS`.
    layer_mode : str
        How the exact solver loads the layer: "indentation" or "rolling" (see :mod:`contact.normal.exact_layer`).
    """

    name: str = AUTO
    exact_cells: int | None = None
    layer_mode: str = "indentation"

    def __post_init__(self):
        if self.name not in NORMAL_CHOICES:
            raise InputError("method.normal", f"must be one of {', '.join(NORMAL_CHOICES)}, got {self.name!r}")
        object.__setattr__(self, "name", resolve_normal_name(self.name, self.layer_mode))
        self.exact_options()                                  # validates exact_cells and layer_mode
        if self.name == "coarse_exact" and self.layer_mode != "indentation":
            raise InputError("method.layer_mode", f"coarse_exact loads the layer in indentation mode only, got "
                             f"{self.layer_mode!r} (use method.normal = \"exact\" for rolling)")

    @property
    def p_max_approximate(self) -> bool:
        """True when this solver's p_max is approximate (Kik-Piotrowski)."""
        return self.name in P_MAX_APPROXIMATE

    def exact_options(self, **overrides):
        """The :class:`contact.normal.exact.ExactOptions` of this choice (InputError naming the key if invalid)."""
        # exact.py is imported here: the Kik-Piotrowski path does not need it
        from contact.normal.exact import DEFAULT_CELLS, ExactOptions

        cells = DEFAULT_CELLS if self.exact_cells is None else self.exact_cells
        return ExactOptions(cells=cells, layer_mode=self.layer_mode, **overrides)


def _method_of(method: NormalMethod | str | None) -> NormalMethod:
    """``method`` as a NormalMethod (a name is accepted for the default options); TypeError for anything else."""
    if method is None:
        return NormalMethod()
    if isinstance(method, str):
        return NormalMethod(method)
    if not isinstance(method, NormalMethod):
        raise TypeError(f"solve_normal_with: method must be a NormalMethod or one of {NORMAL_METHODS}, "
                        f"got {type(method).__name__}")
    return method


def solve_normal_with(prob: NormalProblem, layer: LayerPair | None = None, *extra,
                      method: NormalMethod | str | None = None, **kwargs) -> NormalSolution:
    """Solve the normal problem with the chosen solver.

    Parameters
    ----------
    prob : NormalProblem
        Separation (mm), normal force (N), rolling radius (mm), ``E_MPa`` and ``poisson``.
    layer : LayerPair, optional
        The bodies' Prandtl layers on the problem's strip grid (not modified); None: no layer.
    method : NormalMethod or str, optional
        "auto" (default: "exact"), "kik_piotrowski", "exact" or "coarse_exact", or a :class:`NormalMethod` with the
        exact solver's options.
    **kwargs
        Passed on to :func:`~contact.normal.kik_piotrowski.solve_normal` (``delta_guess_mm``, ``rtol_N``,
        ``loglog_slope_guess``) or :func:`~contact.normal.exact.solve_exact` (the same, for its KP start, and
        ``start``, ``cg_tol``); "coarse_exact" takes ``delta_guess_mm``, ``warm`` and ``rough`` only (the others are KP's).

    Returns
    -------
    NormalSolution
        Patches, approach (mm), peak pressure (MPa), size (mm, mm^2) and layer displacement (mm).

    Raises
    ------
    TypeError
        When ``prob``, ``layer`` or ``method`` has the wrong type.

    """
    if isinstance(prob, NormalMethod):
        raise TypeError("solve_normal_with(prob, layer, method=...): the problem comes first and the method last, "
                        "as a keyword")
    if extra:
        raise TypeError(f"solve_normal_with takes (prob, layer) and keyword arguments; got {len(extra)} more "
                        "positional argument(s) (pass the method as method=...)")
    method = _method_of(method)
    check_arguments(prob, layer, "solve_normal_with")
    if method.name == "kik_piotrowski":
        return solve_normal(prob, layer, **kwargs)
    if method.name == "coarse_exact":
        # coarse_exact.py is imported here, as exact.py below
        from contact.normal.coarse_exact import solve_coarse_exact

        # it starts from a nearby approach and the balance's last grid (warm); the KP iteration's guesses
        # (loglog_slope_guess, rtol_N) are not its
        return solve_coarse_exact(prob, layer, delta_guess_mm=kwargs.get("delta_guess_mm"), warm=kwargs.get("warm"),
                                  rough=bool(kwargs.get("rough", False)))
    # exact.py is imported here: the Kik-Piotrowski path does not need it
    from contact.normal.exact import solve_exact

    return solve_exact(prob, layer, method.exact_options(), **kwargs)
