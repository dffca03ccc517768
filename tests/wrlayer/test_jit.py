"""Loop kernels: compiled by numba, or plain Python for a small run (decided from the run's cost estimate)."""

import json
import os
import subprocess
import sys

import numpy as np

from wrlayer.jit import ENV, SMALL_RUN_S, TieredKernel, jit_mode, kernel, run_mode


@kernel()
def _square(x):
    return x * x


@kernel()
def _sum_of_squares(v):
    total = 0.0
    for i in range(v.size):
        total += _square(v[i])
    return total


def test_a_kernel_compiles_with_its_compiled_callee(monkeypatch):
    monkeypatch.delenv(ENV, raising=False)
    k = TieredKernel(_sum_of_squares.py_func, {})
    assert k(np.arange(4.0)) == 14.0
    assert type(k._compiled).__name__ == "CPUDispatcher" and _square._compiled is not None


def test_never_runs_python_and_gives_the_same_sum(monkeypatch):
    v = np.random.default_rng(1).normal(size=50)
    monkeypatch.setenv(ENV, "never")
    k = TieredKernel(_sum_of_squares.py_func, {})
    python = k(v)
    assert k._compiled is None
    monkeypatch.setenv(ENV, "always")
    assert k(v) == python


def test_run_mode_decides_from_the_estimate_and_restores_the_environment(monkeypatch):
    monkeypatch.delenv(ENV, raising=False)
    with run_mode(SMALL_RUN_S / 2) as python:
        assert python and jit_mode() == "never" and os.environ[ENV] == "never"   # inherited by workers
        with run_mode(SMALL_RUN_S * 2) as inner:   # a block inside a plain-Python one keeps its choice
            assert inner and jit_mode() == "never"
        assert jit_mode() == "never" == os.environ[ENV]
    assert ENV not in os.environ and jit_mode() == "auto"
    with run_mode(SMALL_RUN_S * 2) as python:
        assert not python and jit_mode() == "always"
    monkeypatch.setenv(ENV, "always")
    with run_mode(0.0) as python:
        assert not python
    assert os.environ[ENV] == "always"


def scene_numbers(tmp_path, scene: str, mode: str) -> tuple[dict, str]:
    """result.json of a scene without its timings, and the modules the run imported (numba or not)."""
    out = tmp_path / mode
    env = {k: v for k, v in os.environ.items() if k != ENV}
    if mode != "auto":
        env[ENV] = mode
    code = ("import sys; from contact.__main__ import main; rc = main(sys.argv[1:]); "
            "print('numba' in sys.modules); sys.exit(rc)")
    done = subprocess.run([sys.executable, "-c", code, "simulate", scene, "--out", str(out), "--no-vtk"],
                          check=True, env=env, capture_output=True, text=True)

    def clean(x):
        if isinstance(x, dict):
            return {k: clean(v) for k, v in x.items() if k not in ("timings", "code_version") and not k.endswith("_s")}
        return [clean(v) for v in x] if isinstance(x, list) else x
    return clean(json.loads((out / "result.json").read_text())), done.stdout.strip().splitlines()[-1]


def test_a_small_layered_scene_runs_without_numba_and_agrees_with_the_compiled_run(tmp_path):
    python, numba_loaded = scene_numbers(tmp_path, "scenes/paper_with_layer.toml", "auto")
    assert numba_loaded == "False"
    assert python["passes"] and python["passes"][-1]["p_max_MPa"] > 0
    compiled, numba_loaded = scene_numbers(tmp_path, "scenes/paper_with_layer.toml", "always")
    assert numba_loaded == "True"

    def close(a, b):
        if isinstance(a, dict):
            return a.keys() == b.keys() and all(close(a[k], b[k]) for k in a)
        if isinstance(a, list):
            return len(a) == len(b) and all(close(x, y) for x, y in zip(a, b))
        if isinstance(a, float):
            return abs(a - b) <= 1e-12 * max(abs(a), abs(b), 1e-300)
        return a == b
    assert close(python, compiled)
