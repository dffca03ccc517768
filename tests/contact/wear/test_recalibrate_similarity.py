"""Recalibration by similarity in the wear loop: with ``run.method = "similarity"`` in the template every step's
wheel table is recomputed from the master on the worn profile (no FEM once the master exists), every position of
it, the concave tread and the conforming flange root included: none keeps the scene table's entry, and each whose patch
is like the reference's is anchored to the scene table's direct FEM of the same position on the initial profile. A synthetic
master in the master's cache stands in for the 3D FEM (benchmarks/bench_similarity.py compares the real one with
the direct FEM)."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from calibration.cache import fem_entry, save_entry
from calibration.indentation import load_levels
from calibration.results import IndentationResult
from calibration.similarity.master import grid_points, master_tasks
from contact.wear import condition as condition_mod
from contact.wear.loop import run_wear
from wrlayer.layer_table import LayerTable

TABLES = Path(__file__).resolve().parents[3] / "scenes" / "tables"
#: The template's positions: flange root (conforming, concave), concave tread, flat and convex tread.
POSITIONS = (-37.5, 0.0, 15.0, 30.0, 37.5)

TEMPLATE = """
[run]
model = "3d"
method = "similarity"
master_dir = "{master}"
workers = 1
plots = false
[load]
max_factor = 2.0
n_levels = 3
unload_factors = [1.5, 2.0]
max_increment_factor = 0.3
[mesh]
elements_per_semi_axis = 2
h_max_mm = 12.0
[fit]
n_segments = 3
max_relative_error = 0.2
[[bodies]]
body = "wheel"
profile = "@wheel_profile@"
mate = "@rail_profile@"
wheel_radius_mm = 460.0
positions_mm = [-37.5, 0.0, 15.0, 30.0, 37.5]
"""


def _fake_indentation(a_mm, b_mm, load, convexity) -> IndentationResult:
    """A 3D-like indentation whose lengths scale with sqrt(a b) (the similarity the master relies on)."""
    r, length = a_mm / b_mm, math.sqrt(a_mm * b_mm)
    p_y = 500.0 * (1.6 + 0.05 * math.log(r) - 0.5 * convexity)
    q = np.array([0.0] + load_levels(1.0, load))
    u_pl = length * 2e-3 * (1 + 0.1 * math.log(r)) * np.maximum(q - 1.0, 0.0) ** 1.5
    peaks = [f * p_y for f in sorted(load.unload_factors)]
    res = np.interp(peaks, q * p_y, u_pl)
    return IndentationResult("3d", (q * p_y).tolist(), (1.4e-5 * length * q * p_y + u_pl).tolist(), u_pl.tolist(),
                             p_y, p_y, 1.4e-5 * length, 1e-5, peaks, res.tolist(), [0.0] * len(peaks), 100, 10, 5, 1.0)


def _fake_master(scene, folder: Path) -> None:
    """The synthetic master of the scene's template written into its cache ``folder``."""
    cfg = scene.settings.recalibrate.calibration
    for (c, _, _), t in zip(grid_points(), master_tasks(cfg, cfg.bodies[0].material)):
        save_entry(fem_entry(folder, t.key), _fake_indentation(t.geometry.a_mm, t.geometry.b_mm, cfg.load, c))


def test_each_step_uses_the_worn_profiles_table_from_the_master(make_scene, tmp_path, monkeypatch):
    template = tmp_path / "recal.toml"
    template.write_text(TEMPLATE.format(master=tmp_path / "master"))
    scene = make_scene(wear={"distance_km": 100.0, "steps": 2, "recalibrate": {"config": str(template)}},
                       passes={"max": 3})
    assert not scene.settings.recalibrate.reanchor  # the default: the master alone where an anchor does not apply
    _fake_master(scene, tmp_path / "master")
    seen = []
    real = condition_mod.solve_condition

    def spy(task):
        seen.append((task.step, task.layers.wheel.table))
        return real(task)

    monkeypatch.setattr(condition_mod, "solve_condition", spy)
    run = run_wear(scene, show_progress=False, work_dir=tmp_path / "work")
    assert len(run.steps) == 2
    summary = json.loads((tmp_path / "work" / "calibration" / "step_001_right" / "tables" / "summary.json").read_text())
    assert summary["positions_computed"] == 0 and summary["similarity"]["master_positions_computed"] == 0  # no FEM
    notes = [d["note"] for d in summary["bodies"]["wheel"]["position_details"]]
    wheel_anchors = [k for k in scene.settings.recalibrate.anchors if k[0] == "wheel"]
    assert len(wheel_anchors) == len(LayerTable.read(TABLES / "wheel_S1002_default.json").positions)
    anchored = [n for n in notes if "anchored to the direct FEM of" in n and "wheel_S1002_default.json" in n]
    assert len(anchored) >= len(notes) - 1  # a patch unlike its reference's (here a/b 22 at y = -15) is not
    assert all(n in anchored or "not anchored: the patch (a/b" in n for n in notes)
    (s1, initial), (s2, table) = seen
    assert (s1, s2) == (1, 2)
    scene_table = LayerTable.read(TABLES / "wheel_S1002_default.json")
    assert initial.positions == scene_table.positions
    by_y = {float(p["y_mm"]): p for p in table.positions}
    worn = tmp_path / "work" / "calibration" / "step_001_right" / "wheel.prw"
    assert Path(table.header["profile_source"]) == worn.resolve()
    assert sorted(by_y) == sorted(float(p["y_mm"]) for p in scene_table.positions)
    for p in scene_table.positions:  # every position recalibrated from the master, none kept from the scene
        y = float(p["y_mm"])
        assert by_y[y]["method"] == "similarity"
        assert by_y[y]["first_yield_fem_MPa"] != p["first_yield_fem_MPa"]
        assert not any("not recalibrated" in w for w in by_y[y].get("warnings", []))
    assert sorted(y for y in by_y if y in POSITIONS) == sorted(POSITIONS)


def test_a_patch_that_left_its_anchor_is_computed_by_the_fem_and_anchors_the_next_recalibration(make_scene,
                                                                                                 tmp_path, monkeypatch):
    """reanchor = true: the one position whose worn patch is unlike its scene-table reference (a/b 22
    against 1.8 at y = -15 mm) is computed by the FEM after step 1 (a synthetic FEM stands in, counted); after step
    2 it is anchored to that entry of step 1's table, or computed again if its patch moved on, the others as
    before."""
    from calibration import pipeline
    from calibration.tasks import PositionOutcome

    template = tmp_path / "recal.toml"
    template.write_text(TEMPLATE.format(master=tmp_path / "master"))
    scene = make_scene(wear={"distance_km": 150.0, "steps": 3,
                             "recalibrate": {"config": str(template), "reanchor": True}}, passes={"max": 3})
    assert scene.settings.recalibrate.reanchor
    _fake_master(scene, tmp_path / "master")
    computed = []

    def fem(task):
        computed.append((task.body, task.y_mm))
        return PositionOutcome(task.key, _fake_indentation(task.geometry.a_mm, task.geometry.b_mm, task.load, 0.0))

    monkeypatch.setattr(pipeline, "run_position", fem)
    run_wear(scene, show_progress=False, work_dir=tmp_path / "work")
    step = {k: json.loads((tmp_path / "work" / "calibration" / f"step_00{k}_right" / "tables" / "summary.json")
                          .read_text()) for k in (1, 2)}
    assert step[1]["positions_computed"] == 1 and computed[0] == ("wheel", -15.0)
    shared = tmp_path / "work" / "calibration" / "cache"  # one FEM cache for the sides and steps of the run
    assert (tmp_path / "work" / "calibration" / "step_001_right" / "tables" / "cache").resolve() == shared.resolve()
    assert any(not p.name.startswith("fit-") for p in shared.iterdir())  # the FEM entry is there
    first = {d["y_mm"]: d for d in step[1]["bodies"]["wheel"]["position_details"]}
    assert first[-15.0]["method"] == "direct"
    assert "computed by the direct FEM (the position's new anchor)" in first[-15.0]["note"]
    assert all("anchored to the direct FEM of" in d["note"] for y, d in first.items() if y != -15.0)
    table = LayerTable.read(tmp_path / "work" / "calibration" / "step_001_right" / "tables" / "wheel_layer_table.json")
    assert {p["y_mm"]: p["method"] for p in table.positions}[-15.0] == "direct"
    second = {d["y_mm"]: d for d in step[2]["bodies"]["wheel"]["position_details"]}[-15.0]
    # its reference is now step 1's FEM entry: anchored to it, or its patch compared with that entry's
    step_1_patch = f"is not the reference's (a/b {first[-15.0]['a_mm'] / first[-15.0]['b_mm']:.3g},"
    assert ("step_001_right" in second["note"] and "anchored to the direct FEM of" in second["note"]) or \
        (second["method"] == "direct" and step_1_patch in second["note"]), second


def test_all_solves_a_section_where_its_patch_moved_and_the_next_step_reuses_it(make_scene, tmp_path, monkeypatch):
    """similarity_elastic = "all" in the wear loop: the first recalibration solves the sections whose worn patch left
    the scene table's reference by more than the reuse limits; the second reuses those solves (anchored to them)
    where the patch stayed, and solves only where it moved on. A synthetic elastic solve stands in (counted)."""
    from calibration.similarity import elastic as elastic_mod
    from calibration.similarity.elastic import SectionElastic

    template = tmp_path / "recal.toml"
    template.write_text(TEMPLATE.format(master=tmp_path / "master").replace(
        'method = "similarity"', 'method = "similarity"\nsimilarity_elastic = "all"', 1))
    scene = make_scene(wear={"distance_km": 150.0, "steps": 3, "recalibrate": {"config": str(template)}},
                       passes={"max": 3})
    _fake_master(scene, tmp_path / "master")
    solved = []

    def fake_solve(task):
        solved.append((task.y_mm, task.profile))
        return SectionElastic(800.0 + task.y_mm, 1.5e-5 * math.sqrt(task.geometry.a_mm * task.geometry.b_mm), 0, 0.0)

    monkeypatch.setattr(elastic_mod, "section_elastic", fake_solve)
    run_wear(scene, show_progress=False, work_dir=tmp_path / "work")
    details = {k: {d["y_mm"]: d["note"] for d in json.loads(
        (tmp_path / "work" / "calibration" / f"step_00{k}_right" / "tables" / "summary.json").read_text())
        ["bodies"]["wheel"]["position_details"]} for k in (1, 2)}
    by_step = {k: {y for y, p in solved if f"step_00{k}_right" in str(p)} for k in (1, 2)}
    assert by_step[1] and by_step[1] < set(details[1])  # some moved, not all
    for k in (1, 2):
        assert {y for y, n in details[k].items() if "p_y and c_el from the section's elastic solve" in n} == by_step[k]
    reused = by_step[1] - by_step[2]
    assert reused  # a patch that stayed keeps step 1's solve
    step_1 = str(tmp_path / "work" / "calibration" / "step_001_right" / "tables")
    assert all(f"anchored to the section's elastic solve of {step_1}" in details[2][y] for y in reused)
