"""Calibration by similarity: the master curves scale with the patch size and interpolate in the surface convexity
and log(a/b); the route serves concave, flat and convex positions (conforming ones too) and sends the others to the
direct FEM, naming why, or serves them from the master's nearest point; a master file of another format version is
rebuilt, never read; a run with the master cached computes no FEM (a synthetic master, written into the master's
cache, stands in for the 3D FEM here); a concave position between a small real master's grid points against its own
FEM: tests/calibration/test_similarity_anchor.py (benchmarks/bench_similarity.py compares the real master with the
direct FEM)."""

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
from calibration.similarity.master import (ASPECTS, CONVEXITIES, MasterCurves, MasterFormatError, grid_points,
                                           master_tasks, stored_master)
from calibration.similarity.route import route, similar_indentation
from calibration.similarity.sections import arc_section, patch_convexity, plastic_convexity
from calibration.tasks import make_tasks
from wrlayer.layer_table import LayerTable
from meshes.profiles import get_profile
from wrlayer.errors import InputError

ROOT = Path(__file__).resolve().parents[2]
COARSE = ROOT / "calibration" / "configs" / "test_coarse.toml"
DEFAULT = ROOT / "calibration" / "configs" / "default.toml"


def _fake_indentation(a_mm: float, b_mm: float, cfg, convexity: float = 0.0) -> IndentationResult:
    """A 3D-like indentation with the similarity built in: p_y and the shape depend on a/b and the surface
    convexity, lengths scale with sqrt(a b)."""
    r, length = a_mm / b_mm, math.sqrt(a_mm * b_mm)
    p_y = 500.0 * (1.6 + 0.05 * math.log(r) - 0.5 * convexity)
    q = np.array([0.0] + load_levels(1.0, cfg.load))
    u_pl = length * 2e-3 * (1 + 0.1 * math.log(r) + convexity) * np.maximum(q - 1.0, 0.0) ** 1.5
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
    results = {t.key: _fake_indentation(t.geometry.a_mm, t.geometry.b_mm, cfg, c)
               for (c, _, _), t in zip(grid_points(), tasks)}
    for t in tasks:
        save_entry(fem_entry(Path(cfg.run.master_dir), t.key), results[t.key])
    return MasterCurves.build(cfg, cfg.bodies[0].material, tasks, results)


def test_master_scales_with_patch_size_and_interpolates_in_convexity(tmp_path):
    cfg = _sim_cfg(tmp_path)
    master = _fake_master(cfg)
    assert master.aspect_range == pytest.approx((1 / 20, 20))
    assert master.convexity_range == (CONVEXITIES[0], CONVEXITIES[-1]) and CONVEXITIES[0] < 0 < CONVEXITIES[-1]
    one = similar_indentation(master, 6.0, 3.0)
    two = similar_indentation(master, 12.0, 6.0)
    assert np.allclose(two.u_pl_mm, 2 * np.asarray(one.u_pl_mm)) and two.first_yield_MPa == one.first_yield_MPa
    turned = similar_indentation(master, 3.0, 6.0)  # the same half-space problem turned by 90 degrees
    assert np.allclose(turned.u_pl_mm, one.u_pl_mm)
    for c in (-0.03, 0.0, 0.08):  # the fake is linear in c and in log(a/b): reproduced between grid points
        r = ASPECTS[3]
        a, b = 4.0 * math.sqrt(r), 4.0 / math.sqrt(r)
        exact, got = _fake_indentation(a, b, cfg, c), similar_indentation(master, a, b, c)
        assert got.first_yield_MPa == pytest.approx(exact.first_yield_MPa)
        assert np.allclose(got.residual_fem_mm, exact.residual_fem_mm)
        assert np.allclose(np.interp(exact.p_MPa, got.p_MPa, got.u_pl_mm), exact.u_pl_mm, atol=1e-12)
    concave, convex = similar_indentation(master, 6.0, 3.0, -0.1), similar_indentation(master, 6.0, 3.0, 0.1)
    assert concave.first_yield_MPa > one.first_yield_MPa > convex.first_yield_MPa
    assert MasterCurves.from_dict(json.loads(json.dumps(master.to_dict()))) == master


def test_an_older_master_file_is_rebuilt_not_misread(tmp_path):
    cfg = _sim_cfg(tmp_path)
    master = _fake_master(cfg)
    path = master.write(tmp_path / "master")
    assert stored_master(tmp_path / "master", master.key) == master
    old = {k: v for k, v in master.to_dict().items() if k not in ("format_version", "convexities")}
    path.write_text(json.dumps(old))  # the crown master's form: no format_version, (size, aspect) arrays
    with pytest.raises(MasterFormatError, match=r"format_version: 1 is not this master's format 2"):
        MasterCurves.read(path)
    assert stored_master(tmp_path / "master", master.key) is None
    result = calibrate(cfg, tmp_path / "out", show_progress=False, log=lambda *a: None)  # rebuilt from the cache
    assert result.ok and result.similarity.master_positions_computed == 0
    assert MasterCurves.read(path) == master


def test_route_serves_concave_flat_and_convex_positions(tmp_path):
    cfg = load_config(DEFAULT)
    tasks, _, _ = make_tasks(cfg, tmp_path, False)
    routes = {(t.body, t.y_mm): route(t) for t in tasks}
    served = [k for k, r in routes.items() if r.method == "similarity"]
    assert len(served) >= 27
    for key, sign in ((("wheel", -37.5), -1), (("wheel", 0.0), -1), (("wheel", 37.5), 0), (("rail", 0.0), 1),
                      (("rail", -32.5), 1)):  # flange root and gauge corner are conforming: served as well
        assert routes[key].method == "similarity" and np.sign(round(routes[key].convexity, 3)) == sign
    far = routes[("rail", -35.9)]
    assert far.method == "direct" and "reaches past the profile's end" in far.note
    nearest = route(next(t for t in tasks if (t.body, t.y_mm) == ("rail", -35.9)), outside="nearest")
    assert nearest.method == "similarity" and "served from the master's nearest point" in nearest.note
    turned = dataclasses.replace(tasks[0], geometry=given_geometry(get_profile("60E1"), 0.0, 1.0, 30.0))
    out = route(turned)
    assert out.method == "direct" and "a/b = 0.0333 outside the master's range 0.05..20" in out.note


def test_patch_convexity_of_a_circle_is_b_over_2r():
    for c in (-0.1, -0.02, 0.0, 0.05):
        assert patch_convexity(arc_section(c, 2.0), 0.0, 2.0) == pytest.approx(c, abs=1e-3)
    rail, wheel = get_profile("60E1"), get_profile("S1002")
    assert patch_convexity(rail, 0.0, 5.0) == pytest.approx(5.0 / 600.0, rel=0.02)  # crown R300: convex
    assert patch_convexity(wheel, -37.5, 2.6) < -0.05  # flange root: concave


def test_plastic_curves_come_from_the_wider_convexity_p_y_from_the_patchs(tmp_path):
    """The plastic convexity is the patch's own on a circle (the arc spans 4 b), larger where the 60E1 head's
    curvature grows across the patch towards the gauge corner; the master's p_y and c_el are taken at the patch's
    convexity, u_pl and the residual (at the same multiples of p_y) at the plastic one."""
    for c in (-0.05, 0.05):
        assert plastic_convexity(arc_section(c, 2.0), 0.0, 2.0) == pytest.approx(c, abs=2e-3)
    rail = get_profile("60E1")
    assert plastic_convexity(rail, -25.0, 5.4) > patch_convexity(rail, -25.0, 5.4) + 0.02
    master = _fake_master(_sim_cfg(tmp_path))
    mixed = similar_indentation(master, 6.0, 3.0, 0.1, -0.1)
    elastic, plastic = similar_indentation(master, 6.0, 3.0, 0.1), similar_indentation(master, 6.0, 3.0, -0.1)
    assert mixed.first_yield_MPa == elastic.first_yield_MPa != plastic.first_yield_MPa
    assert mixed.fem_elastic_compliance_mm_per_MPa == elastic.fem_elastic_compliance_mm_per_MPa
    assert mixed.p_MPa == elastic.p_MPa and mixed.u_pl_mm == plastic.u_pl_mm != elastic.u_pl_mm
    assert mixed.residual_fem_mm == plastic.residual_fem_mm
    assert similar_indentation(master, 6.0, 3.0, 0.1, None).u_pl_mm == elastic.u_pl_mm
    served = route(next(t for t in make_tasks(load_config(DEFAULT), tmp_path, False)[0]
                        if (t.body, t.y_mm) == ("rail", -25.0)))
    assert served.plastic_convexity > served.convexity + 0.02


def test_similarity_run_with_a_cached_master_computes_no_fem(tmp_path):
    cfg = _sim_cfg(tmp_path)
    _fake_master(cfg)
    result = calibrate(cfg, tmp_path / "out", show_progress=False, log=lambda *a: None)
    assert result.ok and result.positions_computed == 0 and result.fem_seconds is None
    sim = result.similarity
    assert sim.served == 2 and sim.direct == 0 and sim.master_positions_cached == len(master_tasks(cfg, cfg.bodies[0].material))
    assert len(master_tasks(cfg, cfg.bodies[0].material)) == len(grid_points())
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

