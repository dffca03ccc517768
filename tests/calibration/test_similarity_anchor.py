"""Similarity anchored to a direct FEM: at its reference the anchored result is the direct FEM's at the master's
levels; elsewhere it is the master's shifted by the master's error at the reference (p_y and the compliance by
ratio, u_pl and the residual by the dimensionless difference); a table's direct 3D entries become references, its
similarity entries do not, a malformed one is an InputError naming it; a similarity run with an anchor records it
(a synthetic master stands in for the 3D FEM; benchmarks/bench_similarity_worn.py measures the real one on worn
profiles)."""

import dataclasses
import math
import re
from pathlib import Path

import numpy as np
import pytest

from calibration.pipeline import calibrate
from calibration.similarity.anchor import (DirectReference, anchor, anchored, applies, reference_of_entry,
                                           table_references)
from calibration.similarity.route import route, similar_indentation
from calibration.tasks import make_tasks
from meshes.profiles import get_profile
from wrlayer.errors import InputError
from wrlayer.layer_table import LayerTable

from tests.calibration.test_similarity import _fake_master, _sim_cfg

TABLES = Path(__file__).resolve().parents[2] / "scenes" / "tables"


def _direct_like(master, a_mm, b_mm, convexity, p_y_factor=0.99, u_factor=1.05) -> DirectReference:
    """A 'direct FEM' that differs from the master: p_y 1 % lower, u_pl and the residuals 5 % higher."""
    m = similar_indentation(master, a_mm, b_mm, convexity)
    q = np.asarray(m.p_MPa) / m.first_yield_MPa
    p_y = m.first_yield_MPa * p_y_factor
    peaks = tuple((np.asarray(master.unload_factors) * p_y).tolist())
    return DirectReference("rail", 0.0, a_mm, b_mm, convexity, p_y, tuple((q * p_y).tolist()),
                           tuple((u_factor * np.asarray(m.u_pl_mm)).tolist()), peaks,
                           tuple((u_factor * np.asarray(m.residual_fem_mm)).tolist()),
                           1.02 * m.fem_elastic_compliance_mm_per_MPa, "direct.json")


def test_an_anchor_gives_the_direct_fem_at_its_reference_and_shifts_the_master_elsewhere(tmp_path):
    master = _fake_master(_sim_cfg(tmp_path))
    ref = _direct_like(master, 6.0, 4.0, 0.01)
    anc = anchor(master, ref)
    assert anc.p_y_ratio == pytest.approx(0.99) and anc.compliance_ratio == pytest.approx(1.02)
    at_ref = anchored(similar_indentation(master, 6.0, 4.0, 0.01), anc, ref.length_mm)
    assert at_ref.first_yield_MPa == pytest.approx(ref.p_y_MPa)
    assert np.allclose(at_ref.p_MPa, ref.p_MPa) and np.allclose(at_ref.u_pl_mm, ref.u_pl_mm, atol=1e-12)
    assert np.allclose(at_ref.unload_peaks_MPa, ref.peaks_MPa)
    assert np.allclose(at_ref.residual_fem_mm, ref.residual_mm, atol=1e-12)
    # a worn position: another size and convexity; p_y by the ratio, u_pl by the dimensionless difference x L
    worn_a, worn_b, worn_c = 8.0, 4.5, 0.03
    plain = similar_indentation(master, worn_a, worn_b, worn_c)
    worn = anchored(plain, anc, math.sqrt(worn_a * worn_b))
    assert worn.first_yield_MPa == pytest.approx(0.99 * plain.first_yield_MPa)
    expected = np.asarray(plain.u_pl_mm) + np.asarray(anc.u_pl) * math.sqrt(worn_a * worn_b)
    assert np.allclose(worn.u_pl_mm, np.maximum.accumulate(np.maximum(expected, 0.0)))
    assert np.all(np.diff(worn.u_pl_mm) >= 0) and np.all(np.asarray(worn.residual_fem_mm) >= 0)
    assert worn.fem_elastic_compliance_mm_per_MPa == pytest.approx(1.02 * plain.fem_elastic_compliance_mm_per_MPa)


def test_a_tables_direct_entries_are_references_its_similarity_and_malformed_ones_not():
    table = LayerTable.read(TABLES / "rail_60E1_default.json")
    refs = table_references(table, get_profile("60E1"))
    assert len(refs) == len(table.positions) and all(k[0] == "rail" for k in refs)
    crown = refs["rail", 0.0]
    assert crown.p_y_MPa == table.positions[[p["y_mm"] for p in table.positions].index(0.0)]["first_yield_fem_MPa"]
    assert crown.convexity == pytest.approx(crown.b_mm / 600.0, rel=0.05)  # R300 crown
    entry = dict(table.positions[0])
    assert reference_of_entry("rail", dict(entry, method="similarity"), 0.0, "t.json") is None
    assert reference_of_entry("rail", {k: v for k, v in entry.items() if k != "residual_fem_mm"}, 0.0, "t") is None
    with pytest.raises(InputError, match=r"t.json: position y = -35.9 mm: its direct FEM fields"):
        reference_of_entry("rail", dict(entry, first_yield_fem_MPa="x"), 0.0, "t.json")
    with pytest.raises(InputError, match=r"curves of unequal lengths"):
        reference_of_entry("rail", dict(entry, residual_fem_mm=entry["residual_fem_mm"][:-1]), 0.0, "t.json")


def test_a_similarity_run_with_an_anchor_records_it_and_takes_the_direct_p_y_at_the_reference(tmp_path):
    cfg = _sim_cfg(tmp_path, positions=(0.0,))
    master = _fake_master(cfg)
    plain = calibrate(cfg, tmp_path / "plain", show_progress=False, log=lambda *a: None)
    entry = LayerTable.read(plain.tables["rail"]).positions[0]
    geo = entry["geometry"]
    convexity = route(make_tasks(cfg, tmp_path, False)[0][0]).convexity
    ref = dataclasses.replace(_direct_like(master, geo["a_mm"], geo["b_mm"], convexity), y_mm=0.0)
    result = calibrate(cfg, tmp_path / "anchored", show_progress=False, log=lambda *a: None,
                       anchors={("rail", 0.0): ref})
    got = LayerTable.read(result.tables["rail"]).positions[0]
    assert got["method"] == "similarity"
    assert got["first_yield_fem_MPa"] == pytest.approx(ref.p_y_MPa)
    assert entry["first_yield_fem_MPa"] == pytest.approx(ref.p_y_MPa / 0.99)
    details = result.to_dict()["bodies"]["rail"]["position_details"]
    assert "anchored to the direct FEM of direct.json" in details[0]["note"]


def test_a_patch_unlike_the_references_is_not_anchored_and_says_why(tmp_path):
    cfg = _sim_cfg(tmp_path, positions=(0.0,))
    master = _fake_master(cfg)
    task = make_tasks(cfg, tmp_path, False)[0][0]
    g, convexity = task.geometry, route(task).convexity
    assert applies(_direct_like(master, g.a_mm, g.b_mm, convexity), g.a_mm, g.b_mm, convexity) == ""
    for a, b, c in ((3 * g.a_mm, g.b_mm, convexity), (2 * g.a_mm, 2 * g.b_mm, convexity),
                    (g.a_mm, g.b_mm, convexity + 0.04)):  # a/b x3, size x2, convexity +0.04
        ref = dataclasses.replace(_direct_like(master, a, b, c), y_mm=0.0)
        assert applies(ref, g.a_mm, g.b_mm, convexity).startswith("not anchored: the patch (a/b")
    plain = calibrate(cfg, tmp_path / "plain", show_progress=False, log=lambda *a: None)
    result = calibrate(cfg, tmp_path / "far", show_progress=False, log=lambda *a: None, anchors={("rail", 0.0): ref})
    got, base = (LayerTable.read(r.tables["rail"]).positions[0] for r in (result, plain))
    assert got["first_yield_fem_MPa"] == base["first_yield_fem_MPa"]  # the master's own value
    assert result.to_dict()["bodies"]["rail"]["position_details"][0]["note"].startswith("not anchored")


@pytest.mark.slow
def test_on_a_coarse_mesh_an_anchor_moves_a_nearby_patch_towards_its_own_fem(tmp_path, monkeypatch):
    """A 2 x 2 master (flat and concave c = -0.08, a/b = 1 and 2, L = 3 mm), a 'new' concave position (c = -0.04,
    a/b = 1.4, between the master's grid points) computed directly as the reference, and a 'worn' one nearby
    (c = -0.05, a/b = 1.6, L = 3.3 mm) against its own FEM: the master alone agrees with the 'new' position's own
    FEM (p_y within 2 %, u_pl above 1.2 p_y and the residuals within 4 %), and anchored, p_y and u_pl above 1.2 p_y
    of the 'worn' one are closer to its FEM than the master's alone."""
    from calibration.config import load_config
    from calibration.hertz.geometry import given_geometry
    from calibration.indentation import load_levels
    from calibration.similarity import master as master_mod
    from calibration.similarity.master import MasterCurves, master_key, master_tasks
    from calibration.similarity.sections import arc_section, patch_convexity
    from calibration.tasks import position_task, run_position

    for name, value in (("CONVEXITIES", (-0.08, 0.0)), ("ASPECTS", (1.0, 2.0)), ("SHAPE_ASPECTS", (1.0, 2.0)),
                        ("LENGTHS_MM", (3.0,)), ("SHAPE_LENGTH_MM", 3.0)):
        monkeypatch.setattr(master_mod, name, value)
    cfg = load_config(Path(__file__).resolve().parents[2] / "calibration" / "configs" / "test_coarse.toml")
    material = cfg.bodies[0].material
    tasks = master_tasks(cfg, material)
    master = MasterCurves.build(cfg, material, tasks, {t.key: run_position(t).indentation for t in tasks})

    def direct(c, r, length):
        a, b = length * math.sqrt(r), length / math.sqrt(r)
        section = arc_section(c, b)
        ind = run_position(position_task(cfg, "rail", section, given_geometry(section, 0.0, a, b), material))
        return a, b, ind.indentation

    a0, b0, new = direct(-0.04, 1.4, 3.0)
    assert len(tasks) == 4 and master_key(tasks) == master.key
    sim = similar_indentation(master, a0, b0, patch_convexity(arc_section(-0.04, b0), 0.0, b0))
    assert sim.first_yield_MPa == pytest.approx(new.first_yield_MPa, rel=0.02)
    above = [p for p in load_levels(new.first_yield_MPa, cfg.load) if p > 1.2 * new.first_yield_MPa]
    assert np.allclose(np.interp(above, sim.p_MPa, sim.u_pl_mm), np.interp(above, new.p_MPa, new.u_pl_mm), rtol=0.04)
    assert np.allclose(np.interp(new.unload_peaks_MPa, sim.unload_peaks_MPa, sim.residual_fem_mm),
                       new.residual_fem_mm, rtol=0.04)
    ref = DirectReference("rail", 0.0, a0, b0, -0.04, new.first_yield_MPa, tuple(new.p_MPa), tuple(new.u_pl_mm),
                          tuple(new.unload_peaks_MPa), tuple(new.residual_fem_mm),
                          new.fem_elastic_compliance_mm_per_MPa, "new")
    a1, b1, worn = direct(-0.05, 1.6, 3.3)
    assert applies(ref, a1, b1, -0.05) == ""
    plain = similar_indentation(master, a1, b1, -0.05)
    fixed = anchored(plain, anchor(master, ref), math.sqrt(a1 * b1))
    levels = [p for p in load_levels(worn.first_yield_MPa, cfg.load) if p > 1.2 * worn.first_yield_MPa]
    u_worn = np.interp(levels, worn.p_MPa, worn.u_pl_mm)

    def error(sim):
        return max(abs(sim.first_yield_MPa / worn.first_yield_MPa - 1),
                   float(np.max(np.abs(np.interp(levels, sim.p_MPa, sim.u_pl_mm) / u_worn - 1))))

    assert error(fixed) < error(plain) and error(fixed) < 0.04, (error(fixed), error(plain))


def test_a_bodys_anchor_table_anchors_a_similarity_run_and_a_bad_one_is_refused(tmp_path):
    from calibration.config import parse_config

    cfg = _sim_cfg(tmp_path, positions=(0.0, 5.0))
    _fake_master(cfg)
    table = TABLES / "rail_60E1_default.json"
    anchored_cfg = dataclasses.replace(cfg, bodies=(dataclasses.replace(cfg.bodies[0], anchor_table=str(table)),))
    result = calibrate(anchored_cfg, tmp_path / "out", show_progress=False, log=lambda *a: None)
    notes = [d["note"] for d in result.to_dict()["bodies"]["rail"]["position_details"]]
    assert len(notes) == 2 and all("anchored to the direct FEM of" in n and "rail_60E1_default.json" in n
                                   for n in notes)
    body = {"body": "rail", "profile": "60E1", "mate": "S1002", "positions_mm": [0.0]}
    ok = parse_config({"bodies": [dict(body, anchor_table=str(table))]}, "c.toml", tmp_path)
    assert ok.bodies[0].anchor_table == str(table.resolve())
    for value, message in ((str(tmp_path / "none.json"), re.escape("c.toml: bodies[0].anchor_table: ")),
                           (str(TABLES / "wheel_S1002_default.json"), "is a wheel table, not a rail table")):
        with pytest.raises(InputError, match=message):
            parse_config({"bodies": [dict(body, anchor_table=value)]}, "c.toml", tmp_path)
