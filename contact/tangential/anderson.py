"""Anderson acceleration of a fixed-point iteration x -> G(x) (Walker & Ni 2011, SIAM J. Numer. Anal. 49, "Anderson
acceleration for fixed-point iterations", type II with the last m differences).

After each application g = G(x) with residual f = g - x, the next iterate is g - sum_k gamma_k dG_k where dG_k,
dF_k are the differences of the last m applications and residuals and gamma minimises |f - sum_k gamma_k dF_k|
(normal equations on the m x m Gram matrix, kept up to date one row per step: O(m n) per step). Dimensionless; the
caller projects the mixed iterate back onto its constraints.
"""

from __future__ import annotations

import numpy as np

__all__ = ["Anderson"]


class Anderson:
    """Mixing of the last ``memory`` steps of a fixed-point iteration on vectors of length ``size``."""

    def __init__(self, size: int, memory: int):
        self.memory = int(memory)
        self._df = np.zeros((self.memory, size))
        self._dg = np.zeros((self.memory, size))
        self._gram = np.zeros((self.memory, self.memory))
        self._steps = 0
        self._last: tuple[np.ndarray, np.ndarray] | None = None

    def restart(self) -> None:
        """Forget the history (e.g. when the residual grew)."""
        self._steps = 0
        self._last = None

    def mix(self, x: np.ndarray, g: np.ndarray) -> np.ndarray:
        """The next iterate from the iterate ``x`` and its image ``g`` = G(x) (g itself until two steps exist)."""
        if self.memory <= 0:
            return g
        f = g - x
        if self._last is not None:
            slot = self._steps % self.memory
            np.subtract(f, self._last[0], out=self._df[slot])       # in place: no temporaries of length size
            np.subtract(g, self._last[1], out=self._dg[slot])
            m = min(self._steps + 1, self.memory)
            np.dot(self._df[:m], self._df[slot], out=self._gram[slot, :m])
            self._gram[:m, slot] = self._gram[slot, :m]
            self._steps += 1
        self._last = (f, g)
        m = min(self._steps, self.memory)
        if m == 0:
            return g
        gram = self._gram[:m, :m] + np.diag(np.full(m, 1e-12 * np.trace(self._gram[:m, :m]) / m + 1e-300))
        try:                                             # the ridge keeps nearly dependent differences solvable
            gamma = np.linalg.solve(gram, self._df[:m] @ f)
        except np.linalg.LinAlgError:
            self.restart()
            return g
        out = gamma @ self._dg[:m]
        return np.subtract(g, out, out=out)
