"""The data of the elastoplastic solver (units mm, N, MPa): its options, the converged state (with save/load), the
record of one converged increment and the result of a load path (:mod:`calibration.fem.elastoplastic_solver`)."""

from __future__ import annotations

import io
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np

from calibration.fem.assembly import Discretisation
from calibration.fem.linear_solvers import PRECISIONS, resolve_backend
from wrlayer.atomic_write import atomic_write_bytes
from wrlayer.errors import InputError, require

STRATEGIES = ("pcg", "newton", "modified")
#: the inner CG tolerances of the Newton iterations (:func:`calibration.fem.newton.cg_tolerance`)
CG_FORCINGS = ("fixed", "adaptive", "mismatch")


@dataclass
class SolverOptions:
    """Numerical options. rtol: relative residual tolerance; etol: relative energy tolerance; max_newton:
    iterations per increment (modified Newton gets 10x); max_increment_MPa: largest p0 step (None: the requested
    levels only); min_increment_fraction: step-cut floor relative to the requested step; linear_solver:
    'auto' | 'pardiso' | 'scipy'; strategy: 'pcg' | 'newton' | 'modified'; order: element order (None: the
    mesh's own); dirichlet: {boundary name: components (0=x/y.., 1, 2)} replacing the default
    {"fixed": all, "symmetry": [0]}; cg_rtol: inner CG tolerance relative to the residual; cg_refresh_iters: refactorise the CG
    preconditioner with the current tangent when CG needed more iterations than this; predictor: start each
    increment from the extrapolation of the converged loading branch in the same direction (``predictor_order``); output_label: heads the titles
    of the PNG pictures (e.g. body and position); max_unload_increment_MPa:
    largest step towards a LOWER level (None: max_increment_MPa; unloading is nearly elastic, so one step usually
    converges, and a failed step is cut as any other); factor_precision: 'single' (default) or 'double'
    factorisations with PARDISO (single: 0.6x the solve and factorisation time at 62k dofs; the factorisation only
    preconditions CG or is refined in double precision, so the converged states agree to the Newton tolerance,
    `make bench`, bench_fem; SuperLU is always double); cg_forcing: 'fixed' (every CG to cg_rtol),
    'adaptive' (Eisenstat-Walker choice 2: the CG tolerance of Newton iteration k is gamma (|r_k| / |r_k-1|)^2)
    or 'mismatch' (default, Eisenstat-Walker choice 1: | |r_k| - |r_k-1 - K_t du_k-1| | / |r_k-1|, the
    mismatch between the residual found and the one the last correction's linear model predicted), at most
    cg_rtol_max and at least cg_rtol, and the first iteration's cg_rtol_max: the early corrections of an increment
    are limited by the change of the plastic zone, not by the linear solve (:func:`calibration.fem.newton.
    cg_tolerance`); cg_target_fraction: no CG tolerance below cg_target_fraction * rtol / |r_k| (a correction
    solved far below the Newton tolerance cannot converge sooner; 0: no such floor; measured with 'mismatch'
    against 'adaptive' without the floor: 12 % fewer triangular solves on the direct 3D calibration position, 30 %
    on a rolling pass of the shipped half-space, 11 % on the rolling section at h = a/4, the same results within
    5e-8 and grooves within 6e-7, docs/validation/fem-speed.md); elastic_predictor: start an
    increment from a virgin state, and every unloading increment, from the elastic solution (the state plus
    (p_new - p_old) times the unit-load elastic displacement): elastic loading converges without an iteration,
    and so does an elastic unloading (the return mapping of the residual check verifies that no point re-yields;
    if some do, Newton continues from there); predictor_order: 2 (default) extrapolates the last three converged
    points of the loading branch quadratically in p0, 1 the last two linearly (measured on the default 3D
    calibration: 7-13 % fewer triangular solves than linear, with the branch carried across load stages,
    `make bench`, bench_fem)."""

    rtol: float = 1e-8
    etol: float = 1e-10
    max_newton: int = 25
    max_increment_MPa: float | None = None
    min_increment_fraction: float = 1.0 / 64.0
    linear_solver: str = "auto"
    strategy: str = "pcg"
    order: int | None = None
    dirichlet: dict[str, Sequence[int]] | None = None
    cg_rtol: float = 1e-3
    cg_refresh_iters: int = 12
    predictor: bool = True
    output_label: str = ""
    max_unload_increment_MPa: float | None = None
    verbose: bool = False
    factor_precision: str = "single"
    cg_forcing: str = "mismatch"
    cg_rtol_max: float = 0.1
    elastic_predictor: bool = True
    predictor_order: int = 2
    cg_target_fraction: float = 0.3

    def validate(self) -> None:
        require(0 < self.rtol < 1, "rtol", f"must be in (0, 1), got {self.rtol}")
        require(0 < self.etol < 1, "etol", f"must be in (0, 1), got {self.etol}")
        require(self.max_newton >= 1, "max_newton", f"must be >= 1, got {self.max_newton}")
        require(self.max_increment_MPa is None or self.max_increment_MPa > 0, "max_increment_MPa",
                f"must be > 0 or None, got {self.max_increment_MPa}")
        require(0 < self.min_increment_fraction <= 1, "min_increment_fraction",
                f"must be in (0, 1], got {self.min_increment_fraction}")
        require(self.strategy in STRATEGIES, "strategy", f"must be one of {STRATEGIES}, got {self.strategy!r}")
        resolve_backend(self.linear_solver)
        require(self.cg_forcing in CG_FORCINGS, "cg_forcing", f"must be one of {CG_FORCINGS}, got {self.cg_forcing!r}")
        require(0 <= self.cg_target_fraction < 1, "cg_target_fraction",
                f"must be in [0, 1), got {self.cg_target_fraction}")
        require(0 < self.cg_rtol <= self.cg_rtol_max < 1, "cg_rtol",
                f"need 0 < cg_rtol <= cg_rtol_max < 1, got {self.cg_rtol}, {self.cg_rtol_max}")
        require(self.predictor_order in (1, 2), "predictor_order",
                f"must be 1 (linear) or 2 (quadratic), got {self.predictor_order!r}")
        require(self.factor_precision in PRECISIONS, "factor_precision",
                f"must be one of {PRECISIONS}, got {self.factor_precision!r}")


@dataclass
class SolverState:
    """Converged state: displacement u_mm (n_dofs), Mandel plastic strain and back stress (n_elem, n_qp, 6),
    equivalent plastic strain (n_elem, n_qp), the load level p0_MPa and the stress (MPa, for output)."""

    u_mm: np.ndarray
    plastic_strain: np.ndarray
    back_stress_MPa: np.ndarray
    eq_plastic_strain: np.ndarray
    p0_MPa: float = 0.0
    stress_MPa: np.ndarray | None = None

    @classmethod
    def virgin(cls, disc: Discretisation) -> SolverState:
        shape = (disc.n_elements, disc.n_qp)
        return cls(np.zeros(disc.n_dofs), np.zeros(shape + (6,)), np.zeros(shape + (6,)), np.zeros(shape), 0.0,
                   np.zeros(shape + (6,)))

    def save_state(self, path: str | Path) -> Path:
        """Write the state to ``path`` (.npz) atomically."""
        buf = io.BytesIO()
        arrays = {k: v for k, v in asdict(self).items() if v is not None}
        arrays["p0_MPa"] = np.array(self.p0_MPa)
        np.savez(buf, **arrays)
        return atomic_write_bytes(path, buf.getvalue())


def save_state(state: SolverState, path: str | Path) -> Path:
    """Write ``state`` to ``path`` (.npz) atomically."""
    return state.save_state(path)


def load_state(path: str | Path) -> SolverState:
    """Read a state written by :func:`save_state`; InputError when missing or malformed."""
    path = Path(path)
    try:
        with np.load(path) as z:
            kw = {k: z[k] for k in z.files}
    except (OSError, ValueError) as err:
        raise InputError(str(path), f"cannot read solver state: {err}") from err
    try:
        kw["p0_MPa"] = float(kw["p0_MPa"])
        return SolverState(**kw)
    except (KeyError, TypeError) as err:
        raise InputError(str(path), f"not a solver state file: {err}") from err


@dataclass
class Increment:
    """One converged increment. p0_MPa: load level; u_centre_mm: normal displacement of the load centre,
    positive into the body; n_plastic: quadrature points yielding in this increment; n_yielded: points with
    eq. plastic strain > 0; newton_iters; residuals: relative residual norms per iteration (first = before the
    first solve); energies: relative energy norms; first_yield: first increment with plastic flow;
    requested: this p0 is one of the requested levels (else an automatic sub-step); cg_iters: inner CG
    iterations (pcg strategy); probes_mm: the values of the ``probes`` given to :func:`solve_load_path` (mm)."""

    p0_MPa: float
    u_centre_mm: float
    n_plastic: int
    n_yielded: int
    newton_iters: int
    residuals: list[float]
    energies: list[float]
    first_yield: bool = False
    requested: bool = True
    cg_iters: int = 0
    probes_mm: dict[str, float] = field(default_factory=dict)


@dataclass
class FemResult:
    """Result of :func:`solve_load_path`; see the module docstring. ``branch_points``: the last (up to three)
    converged (p0 in MPa, u in mm) points of the final monotone branch (restart with ``branch_points=``);
    ``output_seconds``: wall time (s) of the field output (``on_level`` and the VTK/PNG files of ``vtk_at``)."""

    history: list[Increment]
    first_yield_p0_MPa: float
    state: SolverState
    centre_mm: np.ndarray | None
    n_dofs: int
    files: list[Path] = field(default_factory=list)
    branch_points: list[tuple[float, np.ndarray]] = field(default_factory=list)
    output_seconds: float = 0.0



__all__ = ["CG_FORCINGS", "FemResult", "Increment", "STRATEGIES", "SolverOptions", "SolverState", "load_state",
           "save_state"]
