"""The calibration FEM's mesh convergence at equal peak pressure: every default position run once (a complete file
is read, not run again), the reference unloading from the default's absolute peaks, and the reported deviations.
The FEM cases are a stub here (the real run: about 10 minutes on 2 cores)."""

import json

import numpy as np
import pytest

import benchmarks.calibration_mesh_convergence as bc
from benchmarks import calibration_mesh_same_pressure as sp
from benchmarks.calibration_mesh_convergence import ROOT
from calibration.config import load_config

PEAKS = load_config(ROOT / "calibration" / "configs" / "default.toml").load.unload_factors


def fake_case(body, y_mm, mesh_kw, load_kw=None, **kw):
    """The default mesh's p_y 1 % above the reference's; at the same absolute peaks the reference's dents 2 % below
    the default's at 1.05 p_y and 0.5 % below from 1.1 p_y up, its u_pl 0.3 % below (power laws in p0)."""
    ref = mesh_kw.get("elements_per_semi_axis") in (6, 8)
    p_y = 800.0 if ref else 808.0
    factors = np.array((load_kw or {}).get("unload_factors", PEAKS))
    dent = 1e-3 * (factors * p_y / 800.0) ** 2
    if ref:
        dent = dent / np.where(factors * p_y < 1.075 * 808.0, 1.02, 1.005)
    levels = np.array([1.0, 1.5, 2.0, 2.5, 3.0]) * (load_kw or {}).get("max_factor", 3.0) / 3.0
    u_pl = 1e-2 * (levels * p_y / 800.0) ** 3 / (1.003 if ref else 1.0)
    return {"body": body, "y_mm": y_mm, "mesh": dict(mesh_kw), "a_mm": 7.0, "b_mm": 5.0, "warning": None,
            "seconds": 1.0, "n_dofs": 100 if ref else 10, "first_yield_MPa": p_y, "threads": 1,
            "p_factor": levels.tolist(), "u_pl_mm": u_pl.tolist(), "peak_factor": factors.tolist(),
            "residual_fem_mm": dent.tolist()}


@pytest.fixture
def stub(monkeypatch):
    calls = []

    def case(*args, **kw):
        calls.append(args[:3])
        return fake_case(*args, **kw)

    monkeypatch.setattr(bc, "convergence_case", case)
    monkeypatch.setattr(sp, "every_position_references",
                        lambda: [("rail", 0.0, "stretched", bc.EVERY_POSITION_REFERENCES["isotropic"]),
                                 ("wheel", 30.0, "stretched", bc.EVERY_POSITION_REFERENCES["extruded"])])
    return calls


def test_each_position_at_the_defaults_absolute_peaks(stub, tmp_path, capsys):
    sp.main([str(tmp_path), "--workers", "1", "--report", str(tmp_path / "report.md")])
    assert len(stub) == 6  # per position: the default, the reference's first-yield probe, the reference
    result = json.loads(sp.position_file(tmp_path, "rail", 0.0).read_text())
    np.testing.assert_allclose(result["peak_pressures_MPa"]["case"], result["peak_pressures_MPa"]["ref"])
    assert result["errors"]["first_yield"] == pytest.approx(0.01)
    text = (tmp_path / "report.md").read_text()
    assert "calibration_mesh_same_pressure" in text and "| wheel y = 30 | 1.40 | 10 / 100 | extruded 6 |" in text
    assert "within 1%: 2; within 2%: 2" in text and "at 1.05 p_y 2.00 %, u_pl 0.30 %" in text
    assert "| +1.00 % | 0.30 % | +2.00, +0.50, +0.50," in text
    sp.main([str(tmp_path), "--workers", "1"])
    assert len(stub) == 6  # complete files are read, not run again
    assert "2 positions at equal peak pressure" in capsys.readouterr().out


def test_no_results_no_table():
    assert sp.markdown([]) == ""
