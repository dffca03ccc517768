"""A small subset of the numerical stress cases (``make stress`` runs the full set, see benchmarks/stress.py).

Contact: 38 random scenes (seeds from 1000 on with at most 20 passes, so that the subset stays fast) must end in an
accepted outcome (all invariants hold, or the project's clear error), plus known failing seeds of the full run as
strict xfails. FEM: three tiny plane-strain cases (step cutting, coarse mesh, beyond the limit load with pcg).
"""

import pytest

from benchmarks.stress_contact import (
    InvariantViolation,
    check_contact_case,
    random_contact_case,
)
from benchmarks.stress_fem import FEM_CASES, run_fem_case


def _fast_seeds(n: int, start: int = 1000, max_passes: int = 20) -> list[int]:
    """The first n seeds from ``start`` on whose case runs at most ``max_passes`` passes."""
    seeds, s = [], start
    while len(seeds) < n:
        if random_contact_case(s).passes <= max_passes:
            seeds.append(s)
        s += 1
    return seeds


_TRUNCATED = ("contact patch reaches the end of the separation table and is silently truncated; solve_normal "
              "should raise InputError instead (benchmarks/stress.py report)")
_KNOWN_FAILING_SEEDS = {126: (_TRUNCATED, InvariantViolation), 486: (_TRUNCATED, InvariantViolation)}
_SEEDS = _fast_seeds(38) + [pytest.param(s, marks=pytest.mark.xfail(strict=True, raises=exc, reason=r))
                            for s, (r, exc) in _KNOWN_FAILING_SEEDS.items()]


@pytest.mark.parametrize("seed", _SEEDS)
def test_random_contact_case(seed):
    assert check_contact_case(random_contact_case(seed)) in ("ok", "clear-error")


_FEM_XFAIL = {"beyond-limit-pcg": "pcg: after a diverged increment the step cutting keeps the stale preconditioner, "
                                  "so every cut step fails, even the elastic ones (calibration/elastoplastic_solver.py)"}
_FEM = [pytest.param(c.name, marks=pytest.mark.xfail(strict=True, reason=_FEM_XFAIL[c.name]))
        if c.name in _FEM_XFAIL else c.name for c in FEM_CASES if c.subset]


@pytest.mark.parametrize("name", _FEM)
def test_fem_stress_case(name):
    result = run_fem_case(next(c for c in FEM_CASES if c.name == name))
    assert result["outcome"] in ("ok", "clear-error"), result
