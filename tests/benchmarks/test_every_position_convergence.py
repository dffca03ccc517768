"""The every-position mesh convergence of the calibration benchmark (full mode): each position of the default
configuration is compared with the reference of its own mesh style. The FEM cases are replaced by a stub here
(the real run takes about 25 minutes); what is tested is the choice of reference and the reported errors."""

import benchmarks.bench_calibration as bc


def test_every_position_uses_the_reference_of_its_mesh_style(monkeypatch):
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
    assert len(rows) == 24 and len(calls) == 48
    styles = {(r["body"], r["y_mm"]): r["style"] for r in rows}
    # the elongated patches of the default run are extruded (a/b >= 4: 5.8-13.6), the others isotropic (a/b <= 3.7)
    assert styles[("wheel", 30.0)] == styles[("wheel", -45.0)] == styles[("wheel", -30.0)] == "extruded"
    assert styles[("rail", 0.0)] == styles[("wheel", -37.5)] == styles[("rail", 15.0)] == "isotropic"
    assert sum(s == "extruded" for s in styles.values()) == 3
    for r in rows:
        assert r["reference"] == bc.EVERY_POSITION_REFERENCES[r["style"]]
        assert abs(r["errors"]["first_yield"] - 0.02) < 1e-12
        assert all(abs(x - 0.02) < 1e-12 for x in r["errors"]["residual_levels"])
    md = bc.every_position_markdown(rows)
    assert len(md) == 2 + 24 and "| rail y = 15 | 1.4 | isotropic | 10 / 100 |" in md[2 + 12]
