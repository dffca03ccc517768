"""End to end: a coarse calibration of one rail position writes a valid table; caching; failures; Dask."""

import dataclasses
import json
import shutil
from pathlib import Path

import numpy as np
import pytest

import calibration.pipeline as pipeline
from calibration.config import load_config
from calibration.pipeline import calibrate, run_calibration
from calibration.run_summary import CalibrationResult
from calibration.tasks import PositionOutcome
from wrlayer.layer_table import LayerTable

ROOT = Path(__file__).resolve().parents[2]
COARSE = ROOT / "calibration" / "configs" / "test_coarse.toml"


def _quiet(*args, **kw):
    pass


@pytest.fixture(scope="module")
def coarse_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("calib")
    cfg = load_config(COARSE)
    result = calibrate(cfg, out, show_progress=False, log=_quiet)
    assert isinstance(result, CalibrationResult) and result.ok
    assert result.tables == {"rail": out / "rail_layer_table.json"}
    summary = result.to_dict()
    assert json.loads((out / "summary.json").read_text()) == json.loads(json.dumps(summary))
    return cfg, out, summary


def test_coarse_rail_position_writes_a_valid_table(coarse_run):
    cfg, out, summary = coarse_run
    assert summary["failed"] == [] and summary["positions_computed"] == 1
    # FEM time of the computed position, apart from the field output (none here: plots off)
    times = summary["fem_seconds"]
    assert 0 < times["per_position_min"] == times["per_position_max"] == times["total"]
    assert times["output_total"] == 0
    table = LayerTable.read(out / "rail_layer_table.json")
    assert table.body == "rail" and table.profile_name == "60E1" and table.y_range_mm == (0.0, 0.0)
    pos = table.positions[0]
    ch = table.characteristic_at(0.0)
    # the operating-range fit: the fewest segments that reach the target (or the most allowed), the element's
    # reverse threshold fitted to the FEM residuals, the errors per level stored (format 4)
    assert 2 <= ch.n_segments <= cfg.fit.max_segments and table.is_version_4
    assert pos["fit_mode"] == "operating_range" and ch.reverse_factor >= 1.0
    assert len(pos["levels_over_p2"]) == len(pos["u_pl_error"]) and len(pos["residual_error"]) == 2
    assert ch.n_segments == cfg.fit.max_segments or max(map(abs, pos["u_pl_error"])) <= cfg.fit.target_error
    assert pos["calibrated_max_MPa"] == pytest.approx(max(pos["fem_points"]["p_MPa"]))
    par = ch.to_parameters()
    assert np.all(par.k_N_per_mm3 > 0) and np.all(par.T0_MPa > 0)
    # the elastic limit of the fit is the FEM first-yield pressure (within 3 %)
    assert ch.elastic_limit_MPa == pytest.approx(pos["first_yield_fem_MPa"], rel=0.03)
    # 3D (the default model): elliptic contact a/b ~ 1.33, von Mises, nu = 0.3: half-space first yield at
    # p0 = 1.62 Y (closed form, Johnson 1985 eq. 3.45); the coarse local model is within 5 % of it
    assert pos["fem"]["model"] == "3d"
    assert pos["first_yield_fem_MPa"] == pytest.approx(1.62 * cfg.bodies[0].material.yield_MPa, rel=0.05)
    # the fitted points reproduce the FEM points within the reported errors
    p = np.asarray(pos["fem_points"]["p_MPa"])
    u = np.asarray(pos["fem_points"]["u_mm"])
    err = ch.displacement(p) - u
    assert np.max(np.abs(err)) == pytest.approx(pos["max_error_mm"], rel=1e-6)
    assert pos["max_error_mm"] <= cfg.fit.max_relative_error * u.max()
    # eq. (8) against the FEM unloading runs: the error is the fit error at the peak plus reverse plasticity
    for e, rev in zip(pos["residual_error_mm"], pos["fem"]["reverse_plasticity_mm"]):
        assert abs(e) <= pos["max_error_mm"] + abs(rev) + 1e-12
    assert len(pos["residual_fem_mm"]) == len(cfg.load.unload_factors)
    assert all(r > 0 for r in pos["residual_fem_mm"][1:])
    csv_text = (out / "rail_layer_table.csv").read_text()
    assert csv_text.splitlines()[0].startswith("body,profile,y_mm")
    header = table.header
    for key in ("material", "mesh", "load", "software", "code_version", "inputs_hash", "fit"):
        assert key in header


def test_second_run_uses_the_cache_and_fit_changes_need_no_fem(coarse_run, tmp_path):
    cfg, out, _ = coarse_run
    work = tmp_path / "copy"
    shutil.copytree(out, work)
    before = (work / "rail_layer_table.json").read_text()
    cold = (work / "summary.json").read_text()
    two_workers = dataclasses.replace(cfg, run=dataclasses.replace(cfg.run, workers=2))
    again = run_calibration(two_workers, work, show_progress=False, log=_quiet)
    assert again["positions_computed"] == 0 and again["positions_cached"] == 1
    assert "fem_seconds" not in again  # nothing computed
    assert (work / "rail_layer_table.json").read_text() == before  # nothing changed: nothing rewritten
    assert (work / "summary.json").read_text() == cold  # the warm run keeps the cold run's record
    assert json.loads((work / "summary_cached.json").read_text())["positions_cached"] == 1
    cfg2 = dataclasses.replace(cfg, fit=dataclasses.replace(cfg.fit, max_segments=2, max_relative_error=1.0))
    refit = run_calibration(cfg2, work, show_progress=False, log=_quiet)
    assert refit["positions_computed"] == 0
    assert LayerTable.read(work / "rail_layer_table.json").characteristic_at(0.0).n_segments == 2


@pytest.mark.slow
def test_new_position_is_computed_alone_and_a_failure_keeps_the_others(coarse_run, tmp_path, monkeypatch):
    cfg, out, _ = coarse_run
    work = tmp_path / "copy"
    shutil.copytree(out, work)
    body = dataclasses.replace(cfg.bodies[0], positions_mm=(-5.0, 0.0, 5.0, 10.0))
    cfg2 = dataclasses.replace(cfg, bodies=(body,))
    real = pipeline.run_position

    def failing_at_5(task):
        if task.y_mm == 5.0:
            return PositionOutcome(task.key, None, f"{task.label}: ConvergenceError: Newton did not converge (test)")
        return real(task)

    monkeypatch.setattr(pipeline, "run_position", failing_at_5)
    summary = run_calibration(cfg2, work, show_progress=False, log=_quiet)
    assert summary["positions_computed"] == 3 and summary["positions_cached"] == 1
    assert [f["y_mm"] for f in summary["failed"]] == [5.0]
    assert "y = 5 mm" in summary["failed"][0]["error"]
    assert json.loads((work / "summary.json").read_text())["failed"][0]["y_mm"] == 5.0
    table = LayerTable.read(work / "rail_layer_table.json")
    assert list(table.y_mm) == [-5.0, 0.0, 10.0] and table.failed[0]["y_mm"] == 5.0
    assert table.characteristic_at(-2.5).n_segments >= 2      # between calibrated neighbours
    for y in (2.0, 5.0, 7.5):                                  # never across the failed position
        with pytest.raises(Exception, match="across the failed calibration at y = 5 mm.*Newton did not converge"):
            table.characteristic_at(y)
    with pytest.raises(Exception, match="outside the calibrated range"):
        table.characteristic_at(11.0)
    from calibration.plots import write_body_plots

    for path in write_body_plots(table, body, work / "plots"):
        assert path.stat().st_size > 1000
    # the failure gone: only the failed position is computed, the table is complete
    monkeypatch.setattr(pipeline, "run_position", real)
    summary = run_calibration(cfg2, work, show_progress=False, log=_quiet)
    assert summary["failed"] == [] and summary["positions_computed"] == 1 and summary["positions_cached"] == 3
    table = LayerTable.read(work / "rail_layer_table.json")
    assert list(table.y_mm) == [-5.0, 0.0, 5.0, 10.0] and table.failed == []
    assert table.characteristic_at(7.5).n_segments >= 2


@pytest.mark.slow
def test_dask_local_cluster_runs_3d_positions_across_workers(coarse_run, tmp_path):
    """Two 3D positions on a local Dask cluster of two worker processes (the cluster path of a calibration): the
    position also computed locally gives the same table entry."""
    distributed = pytest.importorskip("distributed")
    cfg, out, _ = coarse_run
    body = dataclasses.replace(cfg.bodies[0], positions_mm=(0.0, 5.0))
    cfg2 = dataclasses.replace(cfg, bodies=(body,))
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cl:
        summary = run_calibration(cfg2, tmp_path / "dask", scheduler=cl.scheduler_address, show_progress=False,
                                  log=_quiet)
        with distributed.Client(cl) as client:
            assert len(client.scheduler_info()["workers"]) == 2
    assert summary["failed"] == [] and summary["positions_computed"] == 2
    table = LayerTable.read(tmp_path / "dask" / "rail_layer_table.json")
    assert list(table.y_mm) == [0.0, 5.0] and table.header["model"] == "3d"
    a = LayerTable.read(out / "rail_layer_table.json").characteristic_at(0.0)
    b = table.characteristic_at(0.0)
    np.testing.assert_allclose(b.u_mm, a.u_mm, rtol=1e-6)
    np.testing.assert_allclose(b.p_MPa, a.p_MPa, rtol=1e-6)


def test_2d_plane_strain_option_end_to_end(coarse_run, tmp_path):
    """The 2D option still runs; its dent is larger than the 3D one at the same multiple of first yield (the
    plane-strain line load is the a/b -> inf limit, more severe than the a/b ~ 1.3 ellipse)."""
    cfg = load_config(COARSE)
    cfg = dataclasses.replace(cfg, run=dataclasses.replace(cfg.run, model="2d", plots=True),
                              mesh=dataclasses.replace(cfg.mesh, elements_per_semi_axis=3.0, h_max_mm=10.0, order=1))
    summary = run_calibration(cfg, tmp_path, show_progress=False, log=_quiet)
    assert summary["failed"] == []
    pos = LayerTable.read(tmp_path / "rail_layer_table.json").positions[0]
    assert pos["fem"]["model"] == "2d"
    _check_load_path_series(tmp_path / "fields" / "rail_y+000.000mm" / "load_path", pos, cfg)
    # the time of writing the fields is reported apart from the FEM time (none without plots)
    assert pos["fem"]["output_seconds"] > 0 and pos["fem"]["seconds"] > 0
    assert LayerTable.read(coarse_run[1] / "rail_layer_table.json").positions[0]["fem"]["output_seconds"] == 0
    assert pos["p2_MPa"] == pytest.approx(pos["first_yield_fem_MPa"], rel=0.03)
    # plane-strain line contact, von Mises, nu = 0.3: half-space first yield at 1.79 Y (coarse section: 15 %)
    assert pos["first_yield_fem_MPa"] == pytest.approx(1.79 * 500.0, rel=0.15)
    pos3 = LayerTable.read(coarse_run[1] / "rail_layer_table.json").positions[0]
    assert pos["residual_fem_mm"][-1] > 1.1 * pos3["residual_fem_mm"][-1] > 0


def _check_load_path_series(folder: Path, pos: dict, cfg) -> None:
    """The FE fields of the whole load path are a ParaView time series: one .vtu per converged level (loading and
    unloading), listed in load_path.pvd in path order, each with its load level p0_MPa as FieldData."""
    import xml.etree.ElementTree as ET

    import meshio

    sets = ET.parse(folder / "load_path.pvd").getroot().find("Collection").findall("DataSet")
    assert [int(d.get("timestep")) for d in sets] == list(range(len(sets)))
    p0 = [float(meshio.read(folder / d.get("file")).field_data["p0_MPa"][0]) for d in sets]
    p_y = pos["first_yield_fem_MPa"]
    assert p0[0] == 0.0 and max(p0) == pytest.approx(cfg.load.max_factor * p_y, rel=1e-9)
    # loading to each unloading peak, back to zero, and on: zero appears once more per unloading peak
    assert sum(1 for p in p0[1:] if p == 0.0) == len(cfg.load.unload_factors)
    assert any(b < a for a, b in zip(p0, p0[1:]))
    for d in sets:  # every dataset is a full field file
        m = meshio.read(folder / d.get("file"))
        assert {"von_mises_MPa", "eq_plastic_strain", "stress_MPa"} <= set(m.cell_data)
    last = meshio.read(folder / sets[-1].get("file"))
    assert last.cell_data["plastic"][0].sum() > 0  # unloaded after the highest peak: plastic zone kept


def test_output_files_get_the_users_normal_permissions(coarse_run):
    """Every file of a calibration is readable as a plain open() would make it (umask), not 0600."""
    import os

    mask = os.umask(0o022)
    os.umask(mask)
    files = [f for f in coarse_run[1].rglob("*") if f.is_file()]
    assert files
    for f in files:
        assert f.stat().st_mode & 0o777 == 0o666 & ~mask, f


def test_api_calibrates_in_memory_profiles(coarse_run, tmp_path, monkeypatch):
    """calibration.calibrate on a configuration built in Python: the template's profiles replaced by Profile
    objects (as the wear recalibration does with worn profiles). The FEM is the coarse run's result (what is
    tested is the API and the table of an in-memory profile, not the FEM)."""
    import calibration
    from calibration.cache import load_indentation
    from meshes.profiles import get_profile

    cfg, out, _ = coarse_run
    (entry,) = [p for p in (out / "cache").glob("*.json") if not p.name.startswith("fit-")]
    fem = load_indentation(entry)[0]
    monkeypatch.setattr(pipeline, "run_position", lambda task: PositionOutcome(task.key, fem))
    template = calibration.parse_config({"run": {"model": "3d", "workers": 1, "plots": False},
                                         "bodies": [{"body": "rail", "profile": "60E1", "mate": "S1002",
                                                     "positions_mm": [0.0]}]}, "template")
    body = dataclasses.replace(template.bodies[0], profile=get_profile("60E1"), mate=get_profile("S1002"))
    worn = dataclasses.replace(cfg, bodies=(body,))
    result = calibration.calibrate(worn, tmp_path, show_progress=False, log=_quiet)
    assert result.ok and result.positions_computed == 1
    table = LayerTable.read(result.tables["rail"])
    assert table.header["profile"] == "60E1" and table.header["profile_source"] == "60E1 (in memory)"
    assert table.header["mate"] == "S1002 (in memory)"
    reference = LayerTable.read(out / "rail_layer_table.json")
    assert table.positions[0]["characteristic"] == reference.positions[0]["characteristic"]
    again = calibration.calibrate(worn, tmp_path, show_progress=False, log=_quiet)  # same objects: cached
    assert again.positions_computed == 0 and again.positions_cached == 1
