"""bench_similarity --sections: each served position with p_y and c_el from its section's elastic solve compared
with the direct FEM; a 'direct FEM' made of the master's curves at the section's p_y is matched exactly, one
with a 3 % higher u_pl is counted as a miss (a synthetic master on the coarse configuration)."""

import dataclasses

import numpy as np
import pytest

from benchmarks.bench_similarity import DirectFem, _sections_markdown, section_rows
from calibration.similarity.elastic import section_elastics
from calibration.similarity.route import route, task_indentation
from calibration.tasks import make_tasks

from tests.calibration.test_similarity import _fake_master, _sim_cfg


def test_sections_rows_compare_at_the_sections_p_y_and_count_the_misses(tmp_path):
    cfg = _sim_cfg(tmp_path, positions=(0.0,))
    master = _fake_master(cfg)
    tasks = make_tasks(cfg, tmp_path, False)[0]
    t = tasks[0]
    el = section_elastics([t], tmp_path / "direct" / "cache", 1, "", lambda *a: None)[0][t.key]
    r = route(t)
    sim = task_indentation(master, t, r.convexity, r.plastic_convexity)
    s = el.p_y_MPa / sim.first_yield_MPa
    exact = DirectFem(el.p_y_MPa, np.asarray(sim.p_MPa) * s, np.asarray(sim.u_pl_mm),
                      np.asarray(sim.unload_peaks_MPa) * s, np.asarray(sim.residual_fem_mm))
    rows = section_rows(cfg, master, tasks, {(t.body, t.y_mm): exact}, tmp_path / "direct", workers=1)
    assert len(rows) == 1 and rows[0]["p_y"] == pytest.approx(0.0, abs=1e-12)
    assert rows[0]["u_pl"] < 1e-9 and rows[0]["residual"] < 1e-9
    assert "2 % on p_y, u_pl at every level and every residual: 1 of 1" in " ".join(_sections_markdown(rows))
    high = dataclasses.replace(exact, u_pl_mm=1.03 * exact.u_pl_mm)
    rows = section_rows(cfg, master, tasks, {(t.body, t.y_mm): high}, tmp_path / "direct", workers=1)
    assert rows[0]["u_pl"] == pytest.approx(0.03 / 1.03, rel=1e-3)
    assert "every residual: 0 of 1 served" in " ".join(_sections_markdown(rows))


def test_wear_template_sets_the_master_and_the_elastic_rule(tmp_path):
    import tomllib

    from benchmarks.bench_similarity import wear_template

    for rule in ("none", "unanchored", "all"):
        run = tomllib.loads(wear_template(tmp_path, rule))["run"]
        assert run["similarity_elastic"] == rule and run["master_dir"] == str(tmp_path)
        assert run["method"] == "similarity"
