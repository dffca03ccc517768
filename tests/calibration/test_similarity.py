"""Calibration by similarity: the master curves scale with the patch size and interpolate in log(a/b); the route
serves non-conforming positions in the master's range and sends the others to the direct FEM, naming why; a run
with the master cached computes no FEM (a synthetic master, written into the master's cache, stands in for the
3D FEM here; benchmarks/bench_similarity.py compares the real master with the direct FEM)."""

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest

from calibration.cache import fem_entry, save_entry
from calibration.config import load_config, parse_config
from calibration.hertz.geometry import given_geometry
from calibration.indentation import load_levels
from calibration.pipeline import calibrate
from calibration.results import IndentationResult
from calibration.similarity.master import ASPECTS, LENGTHS_MM, MasterCurves, master_tasks
from calibration.similarity.route import route, similar_indentation
from calibration.tasks import make_tasks
from wrlayer.layer_table import LayerTable
from meshes.profiles import get_profile
from wrlayer.errors import InputError

ROOT = Path(__file__).resolve().parents[2]
COARSE = ROOT / "calibration" / "configs" / "test_coarse.toml"


def _fake_indentation(a_mm: float, b_mm: float, cfg) -> IndentationResult:
    """A 3D-like indentation with the similarity built in: p_y and the shape depend on a/b, lengths scale with
    sqrt(a b)."""
    r, length = a_mm / b_mm, math.sqrt(a_mm * b_mm)
    p_y = 500.0 * (1.6 + 0.05 * math.log(r))
    q = np.array([0.0] + load_levels(1.0, cfg.load))
    u_pl = length * 2e-3 * (1 + 0.1 * math.log(r)) * np.maximum(q - 1.0, 0.0) ** 1.5
    c_el = 1.4e-5 * length
    peaks = [f * p_y for f in sorted(cfg.load.unload_factors)]
    res = np.interp(peaks, q * p_y, u_pl) * 1.01
    return IndentationResult("3d", (q * p_y).tolist(), (c_el * q * p_y + u_pl).tolist(), u_pl.tolist(), p_y, p_y,
                             c_el, 1e-5, peaks, res.tolist(), (res - np.interp(peaks, q * p_y, u_pl)).tolist(),
                             100, 10, 5, 1.0)


def _sim_cfg(tmp_path: Path, positions=(-5.0, 0.0), **body):
    cfg = load_config(COARSE)
    run = dataclasses.replace(cfg.run, method="similarity", master_dir=str(tmp_path / "master"))
    return dataclasses.replace(cfg, run=run, bodies=(dataclasses.replace(cfg.bodies[0], positions_mm=positions,
                                                                         **body),))


def _fake_master(cfg) -> MasterCurves:
    tasks = master_tasks(cfg, cfg.bodies[0].material)
    results = {t.key: _fake_indentation(t.geometry.a_mm, t.geometry.b_mm, cfg) for t in tasks}
    for t in tasks:
        save_entry(fem_entry(Path(cfg.run.master_dir), t.key), results[t.key])
    return MasterCurves.build(cfg, cfg.bodies[0].material, tasks, results)


def test_master_scales_with_patch_size_and_is_symmetric_in_aspect(tmp_path):
    cfg = _sim_cfg(tmp_path)
    master = _fake_master(cfg)
    assert master.aspect_range == pytest.approx((1 / 20, 20))
    one = similar_indentation(master, 6.0, 3.0)
    two = similar_indentation(master, 12.0, 6.0)
    assert np.allclose(two.u_pl_mm, 2 * np.asarray(one.u_pl_mm)) and two.first_yield_MPa == one.first_yield_MPa
    turned = similar_indentation(master, 3.0, 6.0)  # the same half-space problem turned by 90 degrees
    assert np.allclose(turned.u_pl_mm, one.u_pl_mm)
    r = ASPECTS[3]  # at a grid ratio the master is reproduced
    exact = _fake_indentation(2.0 * math.sqrt(r), 2.0 / math.sqrt(r), cfg)
    got = similar_indentation(master, 2.0 * math.sqrt(r), 2.0 / math.sqrt(r))
    assert got.first_yield_MPa == pytest.approx(exact.first_yield_MPa)
    assert np.allclose(got.residual_fem_mm, exact.residual_fem_mm)
    assert np.allclose(np.interp(exact.p_MPa, got.p_MPa, got.u_pl_mm), exact.u_pl_mm, atol=1e-12)
    assert MasterCurves.from_dict(json.loads(json.dumps(master.to_dict()))) == master


def test_route_sends_conforming_and_out_of_range_positions_to_the_direct_fem(tmp_path):
    cfg = _sim_cfg(tmp_path, positions=(-35.0, 0.0))
    tasks, _, _ = make_tasks(cfg, tmp_path, False)
    routes = {t.y_mm: route(t, cfg.reference_load_N) for t in tasks}
    assert routes[0.0].method == "similarity" and routes[0.0].note == ""
    assert routes[-35.0].method == "direct" and "conforming contact (b/R = 0.41 > 0.2" in routes[-35.0].note
    flat = dataclasses.replace(tasks[0], geometry=given_geometry(get_profile("60E1"), 0.0, 1.0, 30.0))
    out = route(flat, cfg.reference_load_N)
    assert out.method == "direct" and "a/b = 0.0333 outside the master's range 0.05..20" in out.note


def test_similarity_run_with_a_cached_master_computes_no_fem(tmp_path):
    cfg = _sim_cfg(tmp_path)
    _fake_master(cfg)
    result = calibrate(cfg, tmp_path / "out", show_progress=False, log=lambda *a: None)
    assert result.ok and result.positions_computed == 0 and result.fem_seconds is None
    sim = result.similarity
    assert sim.served == 2 and sim.direct == 0 and sim.master_positions_cached == len(master_tasks(cfg, cfg.bodies[0].material))
    assert len(master_tasks(cfg, cfg.bodies[0].material)) == len(ASPECTS) * len(LENGTHS_MM) - 1  # a = 29 mm left out
    assert sim.master_positions_computed == 0 and sim.seconds_per_position < 0.1  # ms warm (benchmark)
    assert Path(sim.master_files[0]).is_file()
    table = LayerTable.read(result.tables["rail"])
    assert [p["method"] for p in table.positions] == ["similarity", "similarity"]
    assert table.header["model"] == "3d" and table.header["method"] == "similarity"
    details = result.to_dict()["bodies"]["rail"]["position_details"]
    assert [d["method"] for d in details] == ["similarity"] * 2 and details[0]["y_mate_mm"] is not None


def test_similarity_needs_the_3d_model():
    with pytest.raises(InputError, match=r"run.method: 'similarity' needs model = '3d'"):
        parse_config({"run": {"model": "2d", "method": "similarity"},
                      "bodies": [{"body": "rail", "profile": "60E1", "mate": "S1002", "positions_mm": [0.0]}]},
                     "test.toml")


RAIL_FILE = ROOT.parent / "shared" / "reference" / "profiles" / "MBench_UIC60_v3.prr"


@pytest.mark.skipif(not RAIL_FILE.is_file(), reason="Manchester benchmark profiles not available")
def test_a_folder_of_profiles_is_costed_first_then_calibrated_from_the_master(tmp_path):
    from calibration.batch import calibrate_profiles

    folder = tmp_path / "profiles"
    folder.mkdir()
    for name in ("worn_a.prr", "worn_b.prr"):
        (folder / name).write_bytes(RAIL_FILE.read_bytes())
    (folder / "README.md").write_text("not a profile")
    cfg = _sim_cfg(tmp_path, positions=(-8.0, -3.0), inclination=0.0)
    _fake_master(cfg)
    lines = []
    results = calibrate_profiles([folder], cfg, tmp_path / "out", log=lines.append, show_progress=False)
    assert lines[0].startswith("calibration batch: 2 profile file(s) x 0 3D FEM position(s)")
    assert sorted(p.name for p in results) == ["worn_a.prr", "worn_b.prr"]
    for path, result in results.items():
        assert result.ok and result.similarity.served == 2 and result.positions_computed == 0
        assert result.tables["rail"] == tmp_path / "out" / path.stem / "rail_layer_table.json"
    with pytest.raises(InputError, match=r"bodies\.rail\.inclination"):  # a file rail needs its placement
        calibrate_profiles([folder / "worn_a.prr"], _sim_cfg(tmp_path), tmp_path / "out2", log=lines.append)
    with pytest.raises(InputError, match="no profile file"):
        calibrate_profiles([tmp_path / "nothing*.prr"], cfg, tmp_path / "out3")
