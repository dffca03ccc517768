"""benchmarks/bench_similarity_worn.py end to end on synthetic FEM: a 'direct' run (a fake FEM 1 % below the master
in p_y and 5 % above it in u_pl) is both the reference and the 'worn' case, so the master alone misses it and the
anchored master reproduces it; the report counts both and names the positions; with --sections each position's p_y
is its own section's where it is solved (the patch left its reference's), the reference's elsewhere."""

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest

from benchmarks.bench_similarity import _config
from benchmarks.bench_similarity_worn import markdown, run_cases
from calibration import pipeline
from calibration.cache import fem_entry, load_indentation
from calibration.config import load_config
from calibration.pipeline import calibrate
from calibration.tasks import PositionOutcome, make_tasks
from tests.calibration.test_similarity import _fake_indentation, _fake_master

#: The coarse test configuration at two rail positions.
COARSE = Path(__file__).resolve().parents[2] / "calibration" / "configs" / "test_coarse.toml"


def test_the_anchored_master_reproduces_its_reference_where_the_master_alone_misses(tmp_path, monkeypatch):
    config = tmp_path / "case.toml"
    config.write_text(COARSE.read_text().replace("positions_mm = [0.0]", "positions_mm = [-5.0, 0.0]"))
    cfg = load_config(config)
    sim_cfg = dataclasses.replace(cfg, run=dataclasses.replace(cfg.run, method="similarity",
                                                               master_dir=str(tmp_path / "master")))
    _fake_master(sim_cfg)

    def fem(task):  # the 'direct FEM': p_y 1 % lower, u_pl 5 % higher than the fake master's law
        ind = _fake_indentation(task.geometry.a_mm, task.geometry.b_mm, cfg, 0.0)
        scale = 0.99
        p = (np.asarray(ind.p_MPa) * scale).tolist()
        u_pl = (1.05 * np.asarray(ind.u_pl_mm)).tolist()
        peaks = (np.asarray(ind.unload_peaks_MPa) * scale).tolist()
        res = (1.05 * np.asarray(ind.residual_fem_mm)).tolist()
        return PositionOutcome(task.key, dataclasses.replace(
            ind, p_MPa=p, u_pl_mm=u_pl, u_fem_mm=(np.asarray(p) * ind.fem_elastic_compliance_mm_per_MPa
                                                 + np.asarray(u_pl)).tolist(),
            first_yield_MPa=ind.first_yield_MPa * scale, first_yield_anywhere_MPa=ind.first_yield_MPa * scale,
            unload_peaks_MPa=peaks, residual_fem_mm=res))

    monkeypatch.setattr(pipeline, "run_position", fem)
    calibrate(cfg, tmp_path / "direct", show_progress=False, log=lambda *a: None)
    data = run_cases(config, tmp_path / "direct", tmp_path / "master", [(config, tmp_path / "direct")])
    case = data["cases"][0]
    assert case["served"] == 2 and case["anchors_applied"] == 2
    assert case["within"]["anchored"] == 2 and case["within"]["loop"] == 2 and case["within"]["master"] == 0
    assert case["worst"]["anchored"] < 1e-9 < 0.02 < case["worst"]["master"]
    assert all(math.isclose(r["reference"]["convexity"], r["convexity"]) for r in case["rows"])
    text = markdown(data)
    assert "| rail | -5 | served |" in text and "Served 2 of 2 positions" in text
    assert "master 0, anchored everywhere 2, the loop's rule (anchored at the 2 positions" in text
    # the worn case is the reference itself: its direct FEM against itself, at both positions, exactly
    assert case["same_patch"]["positions"] == 2 and case["same_patch"]["worst"] < 1e-12
    assert "The direct FEM against itself: at the 2 served positions" in text
    # with the sections' elastic solves: p_y is the section's (the real coarse mesh's, not the fake FEM's)
    from calibration.similarity.elastic import SectionElastic, elastic_entry

    data = run_cases(config, tmp_path / "direct", tmp_path / "master", [(config, tmp_path / "direct")], True)
    case = data["cases"][0]
    tasks = make_tasks(_config(config, tmp_path / "master"), tmp_path, False)[0]
    for r, t in zip(case["rows"], tasks):
        own = SectionElastic.from_dict(json.loads(elastic_entry(tmp_path / "direct" / "cache", t).read_text()))
        direct_p_y = load_indentation(fem_entry(tmp_path / "direct" / "cache", t.key))[0].first_yield_MPa
        assert r["loop_section_everywhere"]["p_y"] == pytest.approx(own.p_y_MPa / direct_p_y - 1.0, rel=1e-9)
    assert "The loop's rule with p_y and c_el from the position's own section" in markdown(data)
    # "all": the same patches as the references', so their ratios are reused and nothing is solved
    assert all(r["section_reused"] and r["loop_section"] == r["anchored"] for r in case["rows"])
    assert 'similarity_elastic = "all"`: an elastic solve at the 0 positions whose patch left' in markdown(data)
    # "unanchored": both anchors apply, so no section is solved and the rows are the loop's own
    assert all(r["loop_unanchored"] == r["loop"] for r in case["rows"])
    assert 'similarity_elastic = "unanchored"`: an elastic solve at the 0 positions' in markdown(data)


def test_the_quick_mode_says_what_is_missing(tmp_path, monkeypatch):
    import benchmarks.bench_similarity_worn as worn

    for name in ("DIRECT_OUT", "MASTER", "WORN_OUT"):
        monkeypatch.setattr(worn, name, tmp_path / name.lower())
    res = worn.run("quick", tmp_path / "bench")
    assert res["markdown"].startswith("Not measured: ") and "(run the full mode)" in res["markdown"]
    assert len(res["data"]["missing"]) == 2 + len(worn.WORN_CASES)  # master, reference, each worn case
