"""The arc-block check's comparison at equal p0/p_y (no FEM: synthetic curves)."""

from types import SimpleNamespace

import numpy as np
import pytest

from benchmarks.bench_similarity_arc import equal_q_errors, markdown


def _curve(p_y: float, scale: float = 1.0):
    q = np.array([0.0, 1.0, 1.05, 1.1, 1.5, 2.0, 3.0])
    u = scale * np.where(q > 1.0, (q - 1.0) ** 2, 0.0)
    return SimpleNamespace(first_yield_MPa=p_y, p_MPa=q * p_y, u_pl_mm=u, unload_peaks_MPa=np.array([1.5, 3.0]) * p_y,
                           residual_fem_mm=scale * np.array([0.2, 3.0]))


def test_equal_curves_at_another_first_yield_agree_and_a_scaled_one_is_off_by_its_scale():
    u, r = equal_q_errors(_curve(800.0), _curve(880.0))        # the same curve in p0/p_y: no error
    assert np.abs(u).max() == pytest.approx(0.0, abs=1e-12) and np.abs(r).max() == pytest.approx(0.0, abs=1e-12)
    u, r = equal_q_errors(_curve(800.0), _curve(800.0, 1.03))
    assert u.size == 5 and u[-1] == pytest.approx(0.03) and r[-1] == pytest.approx(0.03)
    assert np.all(np.abs(u) <= 0.03 + 1e-12)                   # the floor (half the value at 1.5 p_y) below


def test_the_report_counts_the_positions_within_the_target():
    row = {"body": "rail", "y_mm": 0.0, "a_over_b": 1.3, "length_mm": 6.2, "plastic_convexity": 0.01,
           "arc_vs_direct": {"worst": 0.025}, "master_vs_direct": {"worst": 0.01}, "master_vs_arc": {"worst": 0.005}}
    text = markdown({"missing": "", "rows": [row, {**row, "y_mm": 5.0, "failed": "meshing failed"}]})
    assert "arc block's own FEM at 0 of 1" in text and "the master at 1" in text and "failed: meshing" in text
    assert markdown({"missing": "23 of 23 master positions not in X", "rows": []}).startswith("Not run")


def test_a_mesh_study_run_reads_as_curves_in_MPa():
    from benchmarks.bench_similarity_arc import mesh_study_result

    run = {"first_yield_MPa": 800.0, "p_factor": [0.0, 1.0, 2.0], "u_pl_mm": [0.0, 0.0, 0.01],
           "peak_factor": [1.5, 3.0], "residual_fem_mm": [0.002, 0.02]}
    got = mesh_study_result(run)
    assert got.p_MPa.tolist() == [0.0, 800.0, 1600.0] and got.unload_peaks_MPa.tolist() == [1200.0, 2400.0]
    u, r = equal_q_errors(got, mesh_study_result(run))
    assert np.abs(u).max() == 0.0 and np.abs(r).max() == 0.0


def test_the_report_lists_both_sides_on_finer_meshes():
    row = {"body": "rail", "y_mm": 30.0, "a_over_b": 10.2, "length_mm": 3.2, "plastic_convexity": 0.04,
           "arc_vs_direct": {"worst": 0.027}, "master_vs_direct": {"worst": 0.021}, "master_vs_arc": {"worst": 0.006}}
    fine = {"body": "rail", "y_mm": 30.0, "mesh": {"elements_per_semi_axis": 6, "style": "extruded"},
            "dofs": [32343, 101973], "arc_vs_direct": 0.0271, "fine_arc_vs_fine_direct": 0.0235, "arc_moved": 0.0102,
            "direct_moved": 0.0068}
    text = markdown({"missing": "", "rows": [row], "fine": [fine]})
    assert ("| rail | 30 | elements_per_semi_axis 6, style extruded | 32343 / 101973 | 2.71 | 2.35 | 1.02 | 0.68 |"
            in text)


def test_the_misses_run_again_on_the_studys_finer_mesh_and_both_sides_are_compared(tmp_path, monkeypatch):
    """fine_rows: only a row that misses the target and has a mesh-study file runs again, on that study's finer mesh
    (the task's mesh says so), and its numbers compare the fine arc with the fine direct FEM (a synthetic FEM)."""
    import json

    import benchmarks.bench_similarity_arc as arc_mod
    from calibration.config import load_config
    from calibration.similarity.route import route
    from calibration.tasks import make_tasks

    cfg = load_config(arc_mod.CONFIG)
    tasks = {t.y_mm: t for t in make_tasks(cfg, tmp_path, False)[0] if t.body == "rail" and t.y_mm in (0.0, 5.0)}
    jobs = [(t, route(t), None) for t in tasks.values()]
    rows = [{"body": "rail", "y_mm": y, "arc_vs_direct": {"worst": w}} for y, w in ((0.0, 0.03), (5.0, 0.01))]

    def study_run(p_y, scale):
        c = _curve(p_y, scale)
        return {"first_yield_MPa": p_y, "p_factor": (c.p_MPa / p_y).tolist(), "u_pl_mm": c.u_pl_mm.tolist(),
                "peak_factor": (c.unload_peaks_MPa / p_y).tolist(), "residual_fem_mm": c.residual_fem_mm.tolist()}

    for y in (0.0, 5.0):
        fine = {**study_run(805.0, 1.01), "mesh": {"elements_per_semi_axis": 6}}
        study = {"case": study_run(800.0, 1.0), "ref": fine}
        (tmp_path / f"rail_y{y:g}.json").write_text(json.dumps(study))
    ran = []

    def fake_run(task):
        ran.append(task)
        return SimpleNamespace(error=None, indentation=SimpleNamespace(**vars(_curve(810.0, 1.03)), n_dofs=99))

    monkeypatch.setattr(arc_mod, "_run", fake_run)
    default_arc = SimpleNamespace(**vars(_curve(790.0, 1.02)), n_dofs=11)
    out = arc_mod.fine_rows(cfg, jobs, rows, [default_arc, default_arc], tmp_path, workers=1)
    assert len(ran) == 1 and ran[0].mesh.elements_per_semi_axis == 6        # y = 5 mm is within the target
    assert [f["y_mm"] for f in out] == [0.0] and out[0]["dofs"] == [11, 99]
    assert out[0]["fine_arc_vs_fine_direct"] == pytest.approx(0.02 / 1.01, rel=1e-6)   # 1.03 against 1.01
    assert out[0]["direct_moved"] == pytest.approx(0.01, rel=1e-6)
    assert out[0]["arc_moved"] == pytest.approx(0.01 / 1.02, rel=1e-6)
