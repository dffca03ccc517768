"""The balance's secant: unchanged where it converges; where the function jumps across its root (the secant cycles)
the closest sign change is bisected down to the jump, whose side nearer zero is the root when the caller accepts
that step; a larger jump stays a ConvergenceError."""

import math

import pytest

from contact.wheel_rail.root_finder import secant
from wrlayer.errors import ConvergenceError


def stepped(x: float) -> float:
    """Increasing, with a jump of 0.33 across its root at 5 (-0.19 below, +0.14 above) and a small ripple."""
    return 0.01 * (x - 5.0) + (0.14 if x > 5.0 else -0.19) + 1e-4 * math.sin(40.0 * x)


def test_a_smooth_root_is_the_plain_secants():
    calls = []

    def fun(x):
        calls.append(x)
        return x ** 3 - 2.0

    assert secant(fun, 1.0, 1.5, 1e-14, 50, "cube", ftol=1e-12) == pytest.approx(2.0 ** (1 / 3), rel=1e-12)
    assert len(calls) < 12


def test_a_jump_across_the_root_is_bisected_to_the_side_nearer_zero():
    x = secant(stepped, 0.0, 1.0, 1e-9, 50, "stepped", ftol=1e-8, jump_ftol=0.2)
    assert x == pytest.approx(5.0, abs=1e-8) and x > 5.0 and abs(stepped(x)) < 0.15   # the +0.14 side
    with pytest.raises(ConvergenceError, match="stepped: the secant iteration did not converge"):
        secant(stepped, 0.0, 1.0, 1e-9, 50, "stepped", ftol=1e-8)                       # the jump not accepted
    with pytest.raises(ConvergenceError):
        secant(stepped, 0.0, 1.0, 1e-9, 50, "stepped", ftol=1e-8, jump_ftol=0.1)        # larger than accepted


def test_no_sign_change_is_no_root():
    with pytest.raises(ConvergenceError, match="flat"):
        secant(lambda x: 1.0 + 0.0 * x, 0.0, 1.0, 1e-9, 10, "flat", jump_ftol=1.0)
