"""Sparse direct factorisations of the (symmetric) FE stiffness: MKL PARDISO via pypardiso, SciPy SuperLU fallback.

``Factoriser(backend)`` keeps the symbolic analysis (ordering) of a fixed sparsity pattern and refactorises only
numerically when the values change (PARDISO phases 11 once, then 22; solve = phase 33). The matrices passed in
are full CSR with sorted indices and a symmetric pattern; PARDISO receives the upper triangle (mtype -2, real
symmetric indefinite, so that a singular-ish tangent near the limit load is reported, not silently wrong).
"""

from __future__ import annotations

import ctypes
import glob
import os
import sys

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from wrlayer.errors import ConvergenceError, InputError

if "PYPARDISO_MKL_RT" not in os.environ:  # the MKL runtime next to this interpreter, the shortest path first as
    # pypardiso would pick it, but without its recursive search of the environment on every solver (0.3-1 s each)
    _candidates = sorted(glob.glob(os.path.join(sys.prefix, "lib", "*mkl_rt*")), key=len)
    if _candidates:
        os.environ["PYPARDISO_MKL_RT"] = _candidates[0]

try:  # MKL PARDISO (x86_64 only)
    import pypardiso
    HAVE_PARDISO = True
except ImportError:  # pragma: no cover - depends on the platform
    pypardiso = None
    HAVE_PARDISO = False

BACKENDS = ("auto", "pardiso", "scipy")


def resolve_backend(backend: str) -> str:
    """'auto' -> 'pardiso' when pypardiso is importable, else 'scipy'; InputError for unknown names."""
    if backend not in BACKENDS:
        raise InputError("linear_solver", f"must be one of {BACKENDS}, got {backend!r}")
    if backend == "auto":
        return "pardiso" if HAVE_PARDISO else "scipy"
    if backend == "pardiso" and not HAVE_PARDISO:
        raise InputError("linear_solver", "pardiso requested but pypardiso is not installed")
    return backend


PRECISIONS = ("double", "single")


def _new_pardiso_solver():
    """A pypardiso solver object. pypardiso looks for the MKL runtime on every construction (a recursive glob of
    the environment when ``find_library`` fails: 0.3-1 s, measured); the path it found is kept in
    ``PYPARDISO_MKL_RT``, pypardiso's own setting, so that the next positions of a worker skip the search."""
    solver = pypardiso.PyPardisoSolver(mtype=-2)
    if "PYPARDISO_MKL_RT" not in os.environ and getattr(solver.libmkl, "_name", None):
        os.environ["PYPARDISO_MKL_RT"] = solver.libmkl._name
    return solver


class _PardisoSymmetric:
    """PARDISO handle for one symmetric sparsity pattern; ``factorise(data)`` then ``solve(b)``.

    single=True: factorisation and triangular solves in single precision (MKL iparm(28) = 1; matrix, right-hand
    side and solution are passed as float32 and converted here). The solve then has a relative error of about
    1e-6 to 1e-5 (measured on the 62k-dof wheel mesh: 5e-6): use it as a preconditioner or refine it
    (:meth:`Factoriser.solve_refined`). It halves the factor's memory traffic: triangular solves 38 ms against
    64 ms, factorisations 2.2 s against 3.2 s on the 62k-dof wheel mesh at y = 30 mm, one core; no faster solves
    below ~30k dofs (benchmarks/bench_fem.py measures both on its block).
    """

    def __init__(self, indptr: np.ndarray, indices: np.ndarray, n: int, single: bool = False):
        rows = np.repeat(np.arange(n), np.diff(indptr))
        self.upper = indices >= rows
        counts = np.bincount(rows[self.upper], minlength=n)
        self.ia = np.concatenate([[0], np.cumsum(counts)]).astype(np.int32) + 1
        self.ja = indices[self.upper].astype(np.int32) + 1
        self.n = n
        self.single = bool(single)
        self.dtype = np.float32 if self.single else np.float64
        self.solver = _new_pardiso_solver()
        self.solver.set_iparm(1, 1)     # user-supplied iparm
        self.solver.set_iparm(2, 2)     # nested dissection (METIS) ordering
        self.solver.set_iparm(10, 8)    # pivot perturbation 1e-8
        self.solver.set_iparm(11, 0)    # no scaling (symmetric)
        self.solver.set_iparm(13, 0)    # no weighted matching (symmetric)
        if self.single:
            self.solver.set_iparm(8, 0)   # no iterative refinement inside PARDISO (the caller refines)
            self.solver.set_iparm(28, 1)  # single precision
        self.analysed = False
        self.a = None

    def _call(self, phase: int, b: np.ndarray) -> np.ndarray:
        s = self.solver
        x = np.zeros_like(b)
        err = ctypes.c_int32(0)
        i32p = ctypes.POINTER(ctypes.c_int32)
        fp = ctypes.POINTER(ctypes.c_float if self.single else ctypes.c_double)
        s._mkl_pardiso(s.pt.ctypes.data_as(ctypes.POINTER(s._pt_type[0])), ctypes.byref(ctypes.c_int32(1)),
                       ctypes.byref(ctypes.c_int32(1)), ctypes.byref(ctypes.c_int32(-2)),
                       ctypes.byref(ctypes.c_int32(phase)), ctypes.byref(ctypes.c_int32(self.n)),
                       self.a.ctypes.data_as(fp), self.ia.ctypes.data_as(i32p), self.ja.ctypes.data_as(i32p),
                       s.perm.ctypes.data_as(i32p), ctypes.byref(ctypes.c_int32(1)),
                       s.iparm.ctypes.data_as(i32p), ctypes.byref(ctypes.c_int32(0)),
                       b.ctypes.data_as(fp), x.ctypes.data_as(fp), ctypes.byref(err))
        if err.value != 0:
            raise ConvergenceError(f"PARDISO phase {phase} failed with error {err.value}")
        return x

    def factorise(self, data: np.ndarray) -> None:
        self.a = np.ascontiguousarray(data[self.upper], dtype=self.dtype)
        dummy = np.zeros(self.n, dtype=self.dtype)
        if not self.analysed:
            self._call(11, dummy)
            self.analysed = True
        self._call(22, dummy)

    def solve(self, b: np.ndarray) -> np.ndarray:
        if self.single:  # scale into float32's range (the residuals of a converged state can be tiny)
            scale = float(np.max(np.abs(b)))
            if scale == 0.0 or not np.isfinite(scale):
                return np.zeros(self.n) if scale == 0.0 else np.full(self.n, np.nan)
            x = self._call(33, np.ascontiguousarray(b / scale, dtype=np.float32))
            return x.astype(np.float64) * scale
        return self._call(33, np.ascontiguousarray(b, dtype=np.float64))

    def release(self) -> None:
        if self.analysed:
            self._call(-1, np.zeros(self.n, dtype=self.dtype))
            self.analysed = False

    def __del__(self):  # free MKL memory
        try:
            self.release()
        except Exception:  # noqa: BLE001 - interpreter shutdown
            pass


class _ScipyLU:
    """SciPy SuperLU factorisation (fallback without MKL)."""

    def __init__(self, indptr: np.ndarray, indices: np.ndarray, n: int):
        self.indptr, self.indices, self.n = indptr, indices, n
        self.lu = None

    def factorise(self, data: np.ndarray) -> None:
        A = sp.csr_matrix((data, self.indices, self.indptr), shape=(self.n, self.n)).tocsc()
        try:
            self.lu = spla.splu(A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                                options={"SymmetricMode": True})
        except RuntimeError as err:
            raise ConvergenceError(f"SuperLU factorisation failed: {err}") from err

    def solve(self, b: np.ndarray) -> np.ndarray:
        return self.lu.solve(b)

    def release(self) -> None:
        self.lu = None


class Factoriser:
    """Factorise matrices sharing one symmetric CSR pattern (indptr, indices) and solve with them.

    backend: 'auto' | 'pardiso' | 'scipy'. ``factorise(data)`` replaces the factorisation; ``solve(b)``.
    precision: 'double' or 'single' (PARDISO only; SuperLU is always double): a single-precision solve is
    accurate to about 1e-5 relative, enough for a CG preconditioner; :meth:`solve_refined` adds iterative
    refinement in double precision for the direct uses.
    """

    def __init__(self, indptr: np.ndarray, indices: np.ndarray, n: int, backend: str = "auto",
                 precision: str = "double"):
        if precision not in PRECISIONS:
            raise InputError("factor_precision", f"must be one of {PRECISIONS}, got {precision!r}")
        self.backend = resolve_backend(backend)
        self.single = self.backend == "pardiso" and precision == "single"
        self._impl = (_PardisoSymmetric(indptr, indices, n, single=self.single) if self.backend == "pardiso"
                      else _ScipyLU(indptr, indices, n))
        self.n_factorisations = 0
        self.n_solves = 0

    def factorise(self, data: np.ndarray) -> None:
        self._impl.factorise(data)
        self.n_factorisations += 1

    def solve(self, b: np.ndarray) -> np.ndarray:
        self.n_solves += 1
        x = self._impl.solve(b)
        if not np.all(np.isfinite(x)):
            raise ConvergenceError("linear solve produced non-finite values (singular tangent?)")
        return x

    def solve_refined(self, b: np.ndarray, matvec, rtol: float = 1e-12, max_iter: int = 10,
                      info: dict | None = None) -> np.ndarray:
        """Solve A x = b with the factorisation of A (matvec: x -> A x), refined in double precision until
        |b - A x| <= rtol |b| (single precision: usually two refinement steps, i.e. three solves; double: the
        plain solve, unchanged). info: receives "rz0" = b . (first solve of b)."""
        x = self.solve(b)
        if info is not None:
            info["rz0"] = float(b @ x)
        if not self.single:
            return x
        bnorm = np.linalg.norm(b)
        for _ in range(max_iter):
            r = b - matvec(x)
            if np.linalg.norm(r) <= rtol * bnorm:
                break
            x = x + self.solve(r)
        return x

    def release(self) -> None:
        self._impl.release()


def preconditioned_cg(matvec, b: np.ndarray, precondition, rtol: float = 1e-10,
                      max_iter: int = 200, info: dict | None = None) -> tuple[np.ndarray, int]:
    """Conjugate gradients for the SPD operator ``matvec`` with preconditioner ``precondition`` (a solve).

    Returns (x, iterations); raises ConvergenceError when ``max_iter`` is reached. info: receives "rz0" =
    b . precondition(b), the preconditioner's energy norm of b (the first step computes it anyway), and
    "residual" = |b - A x| of the returned x (CG's recursive residual).
    """
    x = np.zeros_like(b)
    r = b.copy()
    bnorm = np.linalg.norm(b)
    if bnorm == 0.0:
        if info is not None:
            info["rz0"] = info["residual"] = 0.0
        return x, 0
    z = precondition(r)
    p = z.copy()
    rz = r @ z
    if info is not None:
        info["rz0"] = float(rz)
    for it in range(1, max_iter + 1):
        Ap = matvec(p)
        pAp = p @ Ap
        if pAp <= 0.0:
            raise ConvergenceError("preconditioned CG: tangent is not positive definite")
        alpha = rz / pAp
        x += alpha * p
        r -= alpha * Ap
        rnorm = np.linalg.norm(r)
        if rnorm <= rtol * bnorm:
            if info is not None:
                info["residual"] = float(rnorm)
            return x, it
        z = precondition(r)
        rz_new = r @ z
        p = z + (rz_new / rz) * p
        rz = rz_new
    raise ConvergenceError(f"preconditioned CG did not converge in {max_iter} iterations")
