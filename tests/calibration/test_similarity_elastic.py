"""The section's elastic solve of a similarity position: it gives the direct FEM's p_y and elastic compliance (the
same mesh, load and first-yield search), is cached and read back through the safe reader (an unusable entry is
solved again), and a similarity result corrected by it takes them while its plastic curves stay the master's at
equal p0 / p_y (a synthetic master stands in for the 3D FEM master; benchmarks/bench_similarity.py --sections
measures the real one)."""

import dataclasses
import math
import os
from pathlib import Path

import numpy as np
import pytest

from calibration.config import load_config, profile_of
from calibration.fem.material import J2Material
from calibration.indentation import elastic_response, position_model
from calibration.similarity.anchor import anchored
from calibration.similarity.elastic import (REUSE_LIMITS, SectionElastic, elastic_entry, needs_solve,
                                            section_elastic, section_elastics, with_section)
from calibration.similarity.route import route, similar_indentation
from calibration.tasks import make_tasks
from wrlayer.errors import InputError

from tests.calibration.test_similarity import _fake_master, _sim_cfg

COARSE = Path(__file__).resolve().parents[2] / "calibration" / "configs" / "test_coarse.toml"


def _task(tmp_path):
    cfg = load_config(COARSE)
    return cfg, make_tasks(cfg, tmp_path, False)[0][0]


def test_the_sections_elastic_solve_gives_the_direct_fems_p_y_and_compliance(tmp_path):
    cfg, task = _task(tmp_path)
    got = section_elastic(task)
    pm = position_model(profile_of(task.profile), task.geometry, task.model, task.mesh)
    direct = elastic_response(pm, J2Material(**dataclasses.asdict(task.material)), task.geometry, task.mesh,
                              task.linear_solver)
    assert got.p_y_MPa == pytest.approx(direct.p_y_MPa, rel=1e-9)
    assert got.compliance_mm_per_MPa == pytest.approx(direct.compliance_mm_per_MPa["ref"], rel=1e-9)
    assert got.n_dofs == pm.disc.n_dofs and got.seconds > 0


def test_solves_are_cached_and_an_unusable_entry_is_solved_again(tmp_path):
    cfg, task = _task(tmp_path)
    cache = tmp_path / "cache"
    said = []
    first, failed = section_elastics([task], cache, 1, "", said.append)
    assert not failed and elastic_entry(cache, task).is_file()
    again, _ = section_elastics([task], cache, 1, "", said.append)
    assert again[task.key] == first[task.key] and len(said) == 1  # read back, not solved
    for bad in ("{}", '{"p_y_MPa": -1}', "not json"):
        elastic_entry(cache, task).write_text(bad)
        fresh, _ = section_elastics([task], cache, 1, "", said.append)
        assert fresh[task.key].p_y_MPa == pytest.approx(first[task.key].p_y_MPa)
        assert "is invalid" in said[-2] and said[-1].startswith("calibration: elastic solves of 1")
    elastic_entry(cache, task).unlink()
    os.mkfifo(elastic_entry(cache, task))  # never a hang: a miss, solved again
    fresh, _ = section_elastics([task], cache, 1, "", said.append)
    assert fresh[task.key].p_y_MPa == pytest.approx(first[task.key].p_y_MPa)


def test_an_entry_is_validated_field_by_field():
    good = {"p_y_MPa": 900.0, "compliance_mm_per_MPa": 1e-5, "n_dofs": 10, "seconds": 1.0}
    assert SectionElastic.from_dict(good) == SectionElastic(900.0, 1e-5, 10, 1.0)
    for name, value in (("p_y_MPa", 0.0), ("compliance_mm_per_MPa", float("nan")), ("n_dofs", 1.5),
                        ("seconds", "x"), ("p_y_MPa", True)):
        with pytest.raises(InputError, match=name):
            SectionElastic.from_dict(dict(good, **{name: value}), "e.json")
    with pytest.raises(InputError, match="other"):
        SectionElastic.from_dict(dict(good, other=1), "e.json")


def test_a_similarity_result_takes_the_sections_p_y_and_compliance_and_keeps_the_masters_curves(tmp_path):
    cfg = _sim_cfg(tmp_path, positions=(0.0,))
    master = _fake_master(cfg)
    task = make_tasks(cfg, tmp_path, False)[0][0]
    c = route(task).convexity
    plain = similar_indentation(master, task.geometry.a_mm, task.geometry.b_mm, c)
    el = SectionElastic(0.97 * plain.first_yield_MPa, 1.03 * plain.fem_elastic_compliance_mm_per_MPa, 1, 1.0)
    length = math.sqrt(task.geometry.a_mm * task.geometry.b_mm)
    got = anchored(plain, with_section(None, master, task, c, el), length)
    assert got.first_yield_MPa == pytest.approx(el.p_y_MPa)
    assert got.fem_elastic_compliance_mm_per_MPa == pytest.approx(el.compliance_mm_per_MPa)
    q_plain = np.asarray(plain.p_MPa) / plain.first_yield_MPa
    assert np.allclose(np.asarray(got.p_MPa) / got.first_yield_MPa, q_plain)  # the same levels q = p0 / p_y
    assert np.allclose(got.u_pl_mm, plain.u_pl_mm) and np.allclose(got.residual_fem_mm, plain.residual_fem_mm)
    assert np.allclose(got.unload_peaks_MPa, 0.97 * np.asarray(plain.unload_peaks_MPa))


def test_a_similarity_run_with_similarity_elastic_takes_each_sections_p_y_and_says_so(tmp_path):
    from calibration.pipeline import calibrate
    from wrlayer.layer_table import LayerTable

    cfg = _sim_cfg(tmp_path, positions=(0.0,))
    cfg = dataclasses.replace(cfg, run=dataclasses.replace(cfg.run, similarity_elastic="all"))
    _fake_master(cfg)
    result = calibrate(cfg, tmp_path / "out", show_progress=False, log=lambda *a: None)
    entry = LayerTable.read(result.tables["rail"]).positions[0]
    own = section_elastic(make_tasks(cfg, tmp_path, False)[0][0])
    assert entry["method"] == "similarity"
    assert entry["first_yield_fem_MPa"] == pytest.approx(own.p_y_MPa, rel=1e-9)
    assert entry["fem"]["fem_elastic_compliance_mm_per_MPa"] == pytest.approx(own.compliance_mm_per_MPa, rel=1e-9)
    note = result.to_dict()["bodies"]["rail"]["position_details"][0]["note"]
    assert "p_y and c_el from the section's elastic solve" in note
    said = []
    calibrate(cfg, tmp_path / "out", show_progress=False, log=said.append)
    assert not any("elastic solves" in s for s in said)  # cached: nothing solved again


def test_unanchored_solves_only_the_sections_without_an_anchor_that_applies(tmp_path):
    from calibration.pipeline import calibrate
    from calibration.similarity.route import route
    from wrlayer.layer_table import LayerTable

    from tests.calibration.test_similarity_anchor import _direct_like

    cfg = _sim_cfg(tmp_path, positions=(-5.0, 0.0))
    cfg = dataclasses.replace(cfg, run=dataclasses.replace(cfg.run, similarity_elastic="unanchored"))
    master = _fake_master(cfg)
    tasks = make_tasks(cfg, tmp_path, False)[0]
    at0 = next(t for t in tasks if t.y_mm == 0.0)
    ref = dataclasses.replace(_direct_like(master, at0.geometry.a_mm, at0.geometry.b_mm, route(at0).convexity),
                              y_mm=0.0)
    said = []
    result = calibrate(cfg, tmp_path / "out", show_progress=False, log=said.append, anchors={("rail", 0.0): ref})
    assert any(s.startswith("calibration: elastic solves of 1 ") for s in said)  # y = -5 mm only
    by_y = {e["y_mm"]: e for e in LayerTable.read(result.tables["rail"]).positions}
    own = section_elastic(next(t for t in tasks if t.y_mm == -5.0))
    assert by_y[-5.0]["first_yield_fem_MPa"] == pytest.approx(own.p_y_MPa, rel=1e-9)
    assert by_y[0.0]["first_yield_fem_MPa"] == pytest.approx(ref.p_y_MPa)  # the anchor's, not a solve's
    notes = {d["y_mm"]: d["note"] for d in result.to_dict()["bodies"]["rail"]["position_details"]}
    assert "elastic solve" in notes[-5.0] and "elastic solve" not in notes[0.0]


def test_a_solve_is_needed_only_without_a_reference_or_beyond_the_reuse_limits(tmp_path):
    from calibration.similarity.anchor import DirectReference

    _, task = _task(tmp_path)
    a, b = task.geometry.a_mm, task.geometry.b_mm
    ref = DirectReference("rail", task.y_mm, a, b, 0.01, 800.0, (800.0,), (0.0,), (), (), 1e-5)
    assert needs_solve(None, task, 0.01) == "no reference"
    assert needs_solve(ref, task, 0.01) == ""
    assert needs_solve(ref, task, 0.01 + 0.99 * REUSE_LIMITS.convexity) == ""
    assert needs_solve(ref, task, 0.01 + 1.01 * REUSE_LIMITS.convexity).startswith("beyond the reuse limits: the patch")
    for a_ref, b_ref in ((a * 1.01 * REUSE_LIMITS.aspect_factor, b), (a * REUSE_LIMITS.size_factor ** 1.01,
                                                                          b * REUSE_LIMITS.size_factor ** 1.01)):
        assert needs_solve(dataclasses.replace(ref, a_mm=a_ref, b_mm=b_ref), task, 0.01)  # aspect, then size


def test_all_solves_the_sections_whose_patch_left_its_references_and_reuses_the_others(tmp_path):
    from calibration.pipeline import calibrate
    from calibration.similarity.route import route
    from wrlayer.layer_table import LayerTable

    from tests.calibration.test_similarity_anchor import _direct_like

    cfg = _sim_cfg(tmp_path, positions=(-5.0, 0.0))
    cfg = dataclasses.replace(cfg, run=dataclasses.replace(cfg.run, similarity_elastic="all"))
    master = _fake_master(cfg)
    tasks = {t.y_mm: t for t in make_tasks(cfg, tmp_path, False)[0]}
    refs = {}
    for y, shift in ((0.0, 0.0), (-5.0, 0.02)):  # -5 mm: beyond the reuse limits, within the anchor's
        g, c = tasks[y].geometry, route(tasks[y]).convexity
        refs["rail", y] = dataclasses.replace(_direct_like(master, g.a_mm, g.b_mm, c + shift), y_mm=y)
    said = []
    result = calibrate(cfg, tmp_path / "out", show_progress=False, log=said.append, anchors=refs)
    assert any(s.startswith("calibration: elastic solves of 1 ") for s in said)  # y = -5 mm only
    by_y = {e["y_mm"]: e for e in LayerTable.read(result.tables["rail"]).positions}
    assert by_y[-5.0]["first_yield_fem_MPa"] == pytest.approx(section_elastic(tasks[-5.0]).p_y_MPa, rel=1e-9)
    assert by_y[0.0]["first_yield_fem_MPa"] == pytest.approx(refs["rail", 0.0].p_y_MPa)  # the reference's ratio
    notes = {d["y_mm"]: d["note"] for d in result.to_dict()["bodies"]["rail"]["position_details"]}
    assert "anchored to the direct FEM" in notes[-5.0] and "elastic solve" in notes[-5.0]
    assert "anchored to the direct FEM" in notes[0.0] and "elastic solve" not in notes[0.0]
    assert set(result.section_references) == {("rail", -5.0)}  # the next recalibration's reference there


def test_the_boolean_form_still_reads(tmp_path):
    text = COARSE.read_text().replace("[run]", '[run]\nmethod = "similarity"\nsimilarity_elastic = true', 1)
    (tmp_path / "c.toml").write_text(text)
    assert load_config(tmp_path / "c.toml").run.similarity_elastic == "all"
    (tmp_path / "c.toml").write_text(text.replace("similarity_elastic = true", 'similarity_elastic = "unanchored"'))
    assert load_config(tmp_path / "c.toml").run.similarity_elastic == "unanchored"


def test_a_section_solve_anchors_the_next_recalibration_of_its_position_without_a_solve(tmp_path):
    from calibration.pipeline import calibrate
    from wrlayer.layer_table import LayerTable

    cfg = _sim_cfg(tmp_path, positions=(0.0,))
    cfg = dataclasses.replace(cfg, run=dataclasses.replace(cfg.run, similarity_elastic="unanchored"))
    _fake_master(cfg)
    said = []
    first = calibrate(cfg, tmp_path / "step1", show_progress=False, log=said.append)  # no anchor: solved
    assert any(s.startswith("calibration: elastic solves of 1 ") for s in said)
    ref = first.section_references["rail", 0.0]
    assert ref.kind == "section's elastic solve" and ref.source == str(tmp_path / "step1")
    said.clear()
    second = calibrate(cfg, tmp_path / "step2", show_progress=False, log=said.append, anchors=first.section_references)
    assert not any("elastic solves" in s for s in said) and second.section_references == {}
    p_y = [LayerTable.read(r.tables["rail"]).positions[0]["first_yield_fem_MPa"] for r in (first, second)]
    assert p_y[1] == pytest.approx(p_y[0], rel=1e-9)  # the same patch: the section's p_y through the ratio
    note = second.to_dict()["bodies"]["rail"]["position_details"][0]["note"]
    assert f"anchored to the section's elastic solve of {tmp_path / 'step1'}" in note
