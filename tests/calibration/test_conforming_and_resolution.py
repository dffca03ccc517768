"""Conforming positions are detected and calibrated at a load whose Hertz patch fits (with a warning);
a mesh too coarse for the contact is an error naming the setting; S_1 follows the stated rule."""

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from calibration.config import FitSettings, load_config
from calibration.hertz.geometry import HERTZ_B_OVER_R_LIMIT, LocalGeometry, conformity
from calibration.position_fit import first_slope_N_per_mm3
from calibration.position_mesh import MIN_ELEMENTS_PER_SEMI_AXIS, check_resolution
from calibration.results import IndentationResult
from calibration.settings import MeshSettings
from calibration.tasks import make_tasks
from wrlayer.errors import InputError

ROOT = Path(__file__).resolve().parents[2]


def test_gauge_corner_and_flange_root_are_conforming_and_recalibrated(tmp_path):
    cfg = load_config(ROOT / "calibration" / "configs" / "default.toml")
    rail = dataclasses.replace(cfg.bodies[0], positions_mm=(-35.0, 0.0))
    wheel = dataclasses.replace(cfg.bodies[1], positions_mm=(-37.5, 0.0))
    tasks, failed, warnings = make_tasks(dataclasses.replace(cfg, bodies=(rail, wheel)), tmp_path, plots=False)
    assert failed == [] and len(tasks) == 4
    flagged = {(w.body, w.y_mm) for w in warnings}
    assert flagged == {("rail", -35.0), ("wheel", -37.5)}  # the crown and the taping line are not
    for w in warnings:
        assert "conforming contact" in w.message and "calibrated at" in w.message
    for t in tasks:
        geo = t.geometry
        ratio = conformity(geo)
        if (t.body, t.y_mm) in flagged:
            assert ratio == pytest.approx(HERTZ_B_OVER_R_LIMIT, rel=1e-6)
            assert geo.reference_load_N < cfg.reference_load_N
        else:
            assert ratio < HERTZ_B_OVER_R_LIMIT and geo.reference_load_N == cfg.reference_load_N


def test_mesh_too_coarse_for_the_contact_names_the_setting():
    geo = LocalGeometry(0.0, 0.0, None, None, None, None, None, None, 7.0, 5.0, None, None, None, "given")
    check_resolution(geo, "3d", MeshSettings(elements_per_semi_axis=MIN_ELEMENTS_PER_SEMI_AXIS))
    with pytest.raises(InputError, match="mesh.elements_per_semi_axis.*too coarse"):
        check_resolution(geo, "3d", MeshSettings(elements_per_semi_axis=1.5))


def _indentation(**kw) -> IndentationResult:
    base = dict(model="3d", p_MPa=[0.0, 1.0], u_fem_mm=[0.0, 1.0], u_pl_mm=[0.0, 0.0], first_yield_MPa=1.0,
                first_yield_anywhere_MPa=1.0, fem_elastic_compliance_mm_per_MPa=1.0,
                halfspace_compliance_mm_per_MPa=1.0, unload_peaks_MPa=[], residual_fem_mm=[],
                reverse_plasticity_mm=[], n_dofs=1, n_elements=1, newton_iterations=0, seconds=0.0)
    return IndentationResult(**dict(base, **kw))


def test_first_slope_rule():
    ind = _indentation(p_MPa=[0.0, 800.0, 2000.0], u_pl_mm=[0.0, 0.0, 0.09], halfspace_compliance_mm_per_MPa=4e-5)
    s1 = first_slope_N_per_mm3(ind, FitSettings())
    assert 2000.0 / s1 == pytest.approx(0.01 * 0.09)      # elastic part at p_max = 1 % of the inelastic one
    assert first_slope_N_per_mm3(ind, FitSettings(elastic_fraction=0.02)) == pytest.approx(1 / (0.02 * 4e-5))
    with pytest.raises(InputError, match="elastic_tolerance"):
        first_slope_N_per_mm3(dataclasses.replace(ind, u_pl_mm=[0.0, 0.0, 0.0]), FitSettings())
    assert np.isfinite(s1)


def test_shipped_tables_flag_the_conforming_positions_in_json_and_csv():
    import csv
    import io

    from wrlayer.layer_table import LayerTable

    table = LayerTable.read(ROOT / "scenes" / "tables" / "rail_60E1_default.json")
    flagged = {p["y_mm"] for p in table.positions if p.get("warnings")}
    assert flagged == {-35.9, -35.0, -32.5, -30.0}
    rows = list(csv.DictReader(io.StringIO((ROOT / "scenes" / "tables" / "rail_60E1_default.csv").read_text())))
    assert {float(r["y_mm"]) for r in rows if "conforming contact" in r["warnings"]} == flagged
    assert table.to_csv() == (ROOT / "scenes" / "tables" / "rail_60E1_default.csv").read_text()
