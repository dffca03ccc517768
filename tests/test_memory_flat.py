"""Memory stays flat in one process: a discretisation with its kept solver problem is freed as soon as it is
dropped (no reference cycle), and ten rolling blocks and a 100-step wear run in one fresh process grow its peak
resident memory by less than 10 % after the first block / step (benchmarks/bench_fem_memory.py)."""

import gc
import weakref

import pytest

from benchmarks.bench_fem_memory import GROWTH_LIMIT, growth, in_fresh_process
from calibration.fem.assembly import discretise
from calibration.fem.elastoplastic_solver import SolverOptions, solve_load_path
from calibration.fem.material import J2Material
from calibration.fem.verification_meshes import hertz_block
from calibration.hertz.load import HertzLoad


def test_a_dropped_discretisation_is_freed_without_a_garbage_collection():
    mesh = hertz_block(0.5, 1.0, 4.0, order=1)
    disc = discretise(mesh)
    res = solve_load_path(mesh, J2Material(210000.0, 0.3, 500.0), HertzLoad(0.0, 1.0, a_mm=1.0), [100.0],
                          options=SolverOptions(linear_solver="scipy"), disc=disc)
    assert res.history[-1].u_centre_mm > 0 and disc.problem_cache  # the solver problem is kept on the disc
    ref = weakref.ref(disc)
    gc.disable()
    try:
        del disc, res
        assert ref() is None  # reference counting alone freed it (a cycle would wait for a full collection)
    finally:
        gc.enable()


@pytest.mark.slow
def test_rolling_blocks_and_a_long_wear_run_keep_the_peak_memory_flat():
    res = in_fresh_process(blocks=10, wear_steps=100)
    assert len(res["rolling_peak_MiB"]) == 10 and res["wear_steps_done"] == 100
    assert growth(res["rolling_peak_MiB"]) < GROWTH_LIMIT, res["rolling_peak_MiB"]
    assert growth(res["wear_peak_MiB"]) < GROWTH_LIMIT, res["wear_peak_MiB"]
