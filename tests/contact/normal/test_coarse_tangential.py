"""The exact tangential theory's grid of a coarse solution: each cell cut along x by the compiled line loop."""

import numpy as np
import pytest

from contact.normal.coarse_ends import line_ends
from contact.normal.coarse_tangential import refined_along_x


def _per_line_interp(xs, p, power, factor):
    """The rule written with numpy.interp line by line (the independent form of the compiled loop)."""
    dx = float(xs[1] - xs[0])
    x = xs[0] - 0.5 * dx + (np.arange(xs.size * factor) + 0.5) * (dx / factor)
    fine = np.zeros((p.shape[0], x.size))
    loaded = np.flatnonzero(p.max(axis=1) > 0)
    lo, hi = line_ends(p[loaded], xs, dx, power)
    for k, row in enumerate(loaded):
        q = np.concatenate([[0.0], p[row] ** power, [0.0]])
        at = np.concatenate([[lo[k]], xs, [hi[k]]])
        keep = np.concatenate([[True], ((xs > lo[k]) & (xs < hi[k])) | (p[row] > 0), [True]])
        line = np.interp(x, at[keep], q[keep], left=0.0, right=0.0) ** (1.0 / power)
        line[(x <= lo[k]) | (x >= hi[k])] = 0.0
        fine[row] = line * (factor * p[row].sum() / line.sum())
    return x, fine


@pytest.mark.parametrize("power", [1, 2])
def test_refined_lines_keep_their_force_and_follow_the_interpolation(power):
    xs = np.linspace(-3.3, 3.3, 12)
    y = np.linspace(-1.0, 1.0, 9)[:, None]
    p = 900.0 * np.sqrt(np.clip(1.0 - (xs[None, :] / 3.5) ** 2 - y ** 2, 0.0, None))
    p[4, 5:7] = 0.0                                  # a gap inside a line: its cells stay knots at zero
    p[0] = 0.0                                       # an unloaded line stays zero
    x, fine = refined_along_x(xs, p, power, 4)
    x_ref, ref = _per_line_interp(xs, p, power, 4)
    np.testing.assert_array_equal(x, x_ref)
    np.testing.assert_allclose(fine, ref, rtol=1e-12, atol=1e-9)
    np.testing.assert_allclose(fine.sum(axis=1), 4 * p.sum(axis=1), rtol=1e-12)
    assert not fine[0].any() and fine.min() >= 0.0
