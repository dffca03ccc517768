"""The every-position mesh convergence of the calibration benchmark (full mode): each position of the default
configuration is compared with a finer mesh (isotropic 8 per semi-axis, extruded 6 on the most elongated patches).
The FEM cases are replaced by a stub here (the real run takes about 30 minutes); what is tested is the choice of
reference and the reported errors."""

from pathlib import Path

import benchmarks.calibration_mesh_convergence as bc
from calibration.config import load_config

DEFAULT_CONFIG = Path(__file__).resolve().parents[2] / "calibration" / "configs" / "default.toml"


def test_every_position_uses_a_finer_reference_by_aspect_ratio(monkeypatch):
    calls = []

    def fake_case(body, y_mm, mesh_kw, **kw):
        calls.append((body, y_mm, dict(mesh_kw)))
        ref = mesh_kw.get("elements_per_semi_axis") in (6, 8)
        scale = 1.0 if ref else 1.02  # the default 2 % above its reference everywhere
        return {"body": body, "y_mm": y_mm, "mesh": dict(mesh_kw), "a_mm": 7.0, "b_mm": 5.0, "warning": None,
                "seconds": 1.0, "n_dofs": 100 if ref else 10, "first_yield_MPa": 800.0 * scale,
                "p_factor": [1.0, 1.5, 2.0, 2.5], "u_pl_mm": [0.0, 0.01 * scale, 0.04 * scale, 0.09 * scale],
                "residual_fem_mm": [0.01 * scale, 0.04 * scale, 0.09 * scale]}

    monkeypatch.setattr(bc, "convergence_case", fake_case)
    rows = bc.convergence_every_position()
    n = sum(len(b.positions_mm) for b in load_config(DEFAULT_CONFIG).bodies)  # every position of the default run
    assert n >= 24 and len(rows) == n and len(calls) == 2 * n
    refs = {(r["body"], r["y_mm"]): r["reference"] for r in rows}
    # the default mesh is the stretched one everywhere; the most elongated patches (a/b >= 4: 5.8-13.6) are
    # compared with the extruded 6, the others with the isotropic 8
    assert {r["style"] for r in rows} == {"stretched"}
    for key in (("wheel", 30.0), ("wheel", -45.0), ("wheel", -30.0)):
        assert refs[key] == bc.EVERY_POSITION_REFERENCES["extruded"]
    assert sum(ref == bc.EVERY_POSITION_REFERENCES["extruded"] for ref in refs.values()) == 6  # with the field-side ones
    assert refs[("rail", 15.0)] == refs[("rail", 0.0)] == bc.EVERY_POSITION_REFERENCES["isotropic"]
    for r in rows:
        assert abs(r["errors"]["first_yield"] - 0.02) < 1e-12
        assert all(abs(x - 0.02) < 1e-12 for x in r["errors"]["residual_levels"])
    md = bc.every_position_markdown(rows)
    assert len(md) == 2 + n and "| rail y = 15 | 1.4 | stretched | 10 / 100 | 1.0 / 1 | isotropic 8 |" in md[2 + 12]
