"""Tiered kernels: plain Python until the work budget is spent, then numba; the same numbers either way."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from wrlayer.jit import TieredKernel, kernel


@kernel()
def _square(x):
    return x * x


@kernel(size=lambda v: v.size, budget=10)
def _sum_of_squares(v):
    total = 0.0
    for i in range(v.size):
        total += _square(v[i])
    return total


def test_kernel_runs_python_within_the_budget_then_compiled(monkeypatch):
    monkeypatch.delenv("WRLAYER_JIT", raising=False)
    k = TieredKernel(_sum_of_squares.py_func, _sum_of_squares.size, 10, {})
    v = np.arange(4.0)
    assert k(v) == 14.0 and k._compiled is None and k.spent == 4
    assert k(np.arange(8.0)) == 140.0 and k._compiled is not None    # 4 + 8 > 10: compiled, callee included
    assert type(k._compiled).__name__ == "CPUDispatcher"


def test_modes_and_identical_numbers(monkeypatch):
    v = np.random.default_rng(1).normal(size=50)
    monkeypatch.setenv("WRLAYER_JIT", "never")
    k = TieredKernel(_sum_of_squares.py_func, _sum_of_squares.size, 10, {})
    python = k(v)
    assert k._compiled is None
    monkeypatch.setenv("WRLAYER_JIT", "always")
    assert k(v[:1]) == v[0] ** 2 and k._compiled is not None
    assert k(v) == python


def test_zero_budget_compiles_at_the_first_call(monkeypatch):
    monkeypatch.delenv("WRLAYER_JIT", raising=False)
    k = TieredKernel(_square.py_func, None, 0, {"fastmath": True})
    assert k(3.0) == 9.0 and k._compiled is not None


def scene_numbers(tmp_path, mode: str) -> dict:
    """result.json of the layered paper scene (Kik-Piotrowski, Prandtl layer, FASTSIM) without its timings."""
    out = tmp_path / mode
    subprocess.run([sys.executable, "-m", "contact", "simulate", "scenes/paper_with_layer.toml", "--out", str(out),
                    "--no-vtk"], check=True, env={**os.environ, "WRLAYER_JIT": mode}, capture_output=True)

    def clean(x):
        if isinstance(x, dict):
            return {k: clean(v) for k, v in x.items() if k not in ("timings", "code_version") and not k.endswith("_s")}
        return [clean(v) for v in x] if isinstance(x, list) else x
    return clean(json.loads((out / "result.json").read_text()))


def test_a_layered_scene_gives_the_same_numbers_in_python_and_compiled(tmp_path):
    python = scene_numbers(tmp_path, "never")
    assert python["passes"] and python["passes"][-1]["p_max_MPa"] > 0
    assert python == scene_numbers(tmp_path, "always")
