"""Sparse direct factorisations of the (symmetric) FE stiffness: MKL PARDISO via pypardiso, SciPy SuperLU fallback.

``Factoriser(backend)`` keeps the symbolic analysis (ordering) of a fixed sparsity pattern and refactorises only
numerically when the values change (PARDISO phases 11 once, then 22; solve = phase 33). The matrices passed in
are full CSR with sorted indices and a symmetric pattern; PARDISO receives the upper triangle (mtype -2, real
symmetric indefinite, so that a singular-ish tangent near the limit load is reported, not silently wrong).
"""

from __future__ import annotations

import ctypes

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from wrlayer.errors import ConvergenceError, InputError

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


class _PardisoSymmetric:
    """PARDISO handle for one symmetric sparsity pattern; ``factorise(data)`` then ``solve(b)``."""

    def __init__(self, indptr: np.ndarray, indices: np.ndarray, n: int):
        rows = np.repeat(np.arange(n), np.diff(indptr))
        self.upper = indices >= rows
        counts = np.bincount(rows[self.upper], minlength=n)
        self.ia = np.concatenate([[0], np.cumsum(counts)]).astype(np.int32) + 1
        self.ja = indices[self.upper].astype(np.int32) + 1
        self.n = n
        self.solver = pypardiso.PyPardisoSolver(mtype=-2)
        self.solver.set_iparm(1, 1)     # user-supplied iparm
        self.solver.set_iparm(2, 2)     # nested dissection (METIS) ordering
        self.solver.set_iparm(10, 8)    # pivot perturbation 1e-8
        self.solver.set_iparm(11, 0)    # no scaling (symmetric)
        self.solver.set_iparm(13, 0)    # no weighted matching (symmetric)
        self.analysed = False
        self.a = None

    def _call(self, phase: int, b: np.ndarray) -> np.ndarray:
        s = self.solver
        x = np.zeros_like(b)
        err = ctypes.c_int32(0)
        i32p, f64p = ctypes.POINTER(ctypes.c_int32), ctypes.POINTER(ctypes.c_double)
        s._mkl_pardiso(s.pt.ctypes.data_as(ctypes.POINTER(s._pt_type[0])), ctypes.byref(ctypes.c_int32(1)),
                       ctypes.byref(ctypes.c_int32(1)), ctypes.byref(ctypes.c_int32(-2)),
                       ctypes.byref(ctypes.c_int32(phase)), ctypes.byref(ctypes.c_int32(self.n)),
                       self.a.ctypes.data_as(f64p), self.ia.ctypes.data_as(i32p), self.ja.ctypes.data_as(i32p),
                       s.perm.ctypes.data_as(i32p), ctypes.byref(ctypes.c_int32(1)),
                       s.iparm.ctypes.data_as(i32p), ctypes.byref(ctypes.c_int32(0)),
                       b.ctypes.data_as(f64p), x.ctypes.data_as(f64p), ctypes.byref(err))
        if err.value != 0:
            raise ConvergenceError(f"PARDISO phase {phase} failed with error {err.value}")
        return x

    def factorise(self, data: np.ndarray) -> None:
        self.a = np.ascontiguousarray(data[self.upper], dtype=np.float64)
        dummy = np.zeros(self.n)
        if not self.analysed:
            self._call(11, dummy)
            self.analysed = True
        self._call(22, dummy)

    def solve(self, b: np.ndarray) -> np.ndarray:
        return self._call(33, np.ascontiguousarray(b, dtype=np.float64))

    def release(self) -> None:
        if self.analysed:
            self._call(-1, np.zeros(self.n))
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
    """

    def __init__(self, indptr: np.ndarray, indices: np.ndarray, n: int, backend: str = "auto"):
        self.backend = resolve_backend(backend)
        cls = _PardisoSymmetric if self.backend == "pardiso" else _ScipyLU
        self._impl = cls(indptr, indices, n)
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

    def release(self) -> None:
        self._impl.release()


def preconditioned_cg(matvec, b: np.ndarray, precondition, rtol: float = 1e-10,
                      max_iter: int = 200) -> tuple[np.ndarray, int]:
    """Conjugate gradients for the SPD operator ``matvec`` with preconditioner ``precondition`` (a solve).

    Returns (x, iterations); raises ConvergenceError when ``max_iter`` is reached.
    """
    x = np.zeros_like(b)
    r = b.copy()
    bnorm = np.linalg.norm(b)
    if bnorm == 0.0:
        return x, 0
    z = precondition(r)
    p = z.copy()
    rz = r @ z
    for it in range(1, max_iter + 1):
        Ap = matvec(p)
        pAp = p @ Ap
        if pAp <= 0.0:
            raise ConvergenceError("preconditioned CG: tangent is not positive definite")
        alpha = rz / pAp
        x += alpha * p
        r -= alpha * Ap
        if np.linalg.norm(r) <= rtol * bnorm:
            return x, it
        z = precondition(r)
        rz_new = r @ z
        p = z + (rz_new / rz) * p
        rz = rz_new
    raise ConvergenceError(f"preconditioned CG did not converge in {max_iter} iterations")
