"""The layer-table format: write/read round trip, validation, interpolation along the profile, CSV export."""

import csv
import io
import json

import numpy as np
import pytest

from wrlayer.characteristic import Characteristic
from wrlayer.layer_table import FORMAT, LayerTable
from wrlayer.errors import InputError


def _entry(y, scale):
    ch = Characteristic(np.array([0.0, 0.001, 0.01, 0.05]) * scale, np.array([0.0, 800.0, 1100.0, 1500.0]))
    par = ch.to_parameters()
    return {"y_mm": y, "characteristic": ch.to_dict(), "n_segments": 3, "k_N_per_mm3": par.k_N_per_mm3.tolist(),
            "T0_MPa": par.T0_MPa.tolist(), "max_error_mm": 1e-4, "rms_error_mm": 5e-5,
            "geometry": {"a_mm": 7.0, "b_mm": 5.0}}


def _table(tmp_path):
    t = LayerTable({"body": "rail", "profile": "60E1", "inputs_hash": "x"},
                   [_entry(-10.0, 1.0), _entry(0.0, 2.0), _entry(10.0, 1.5)],
                   [{"y_mm": 5.0, "error": "rail 60E1 y = 5 mm: ConvergenceError: ..."}])
    paths = t.write(tmp_path / "rail.json", tmp_path / "rail.csv")
    return t, paths


def test_round_trip_and_queries(tmp_path):
    t, (jp, cp) = _table(tmp_path)
    r = LayerTable.read(jp)
    assert r.body == "rail" and r.profile_name == "60E1" and r.y_range_mm == (-10.0, 10.0)
    assert r.failed[0]["y_mm"] == 5.0
    for y, ch in zip(r.y_mm, t.characteristics):  # exact at the calibrated positions
        np.testing.assert_array_equal(r.characteristic_at(y).u_mm, ch.u_mm)
    mid = r.characteristic_at(-5.0)
    u = np.linspace(0, 0.05, 11)
    np.testing.assert_allclose(mid.pressure(u), 0.5 * (t.characteristics[0].pressure(u)
                                                        + t.characteristics[1].pressure(u)), rtol=1e-12)
    assert r.to_json() == jp.read_text()
    rows = list(csv.DictReader(io.StringIO(cp.read_text())))
    assert [float(x["y_mm"]) for x in rows] == [-10.0, 0.0, 10.0]
    assert float(rows[1]["k1_N_per_mm3"]) == pytest.approx(t.characteristics[1].to_parameters().k_N_per_mm3[0])


@pytest.mark.parametrize("y", [-10.5, 11.0, float("nan")])
def test_outside_the_calibrated_range_names_the_position_and_range(tmp_path, y):
    _, (jp, _) = _table(tmp_path)
    with pytest.raises(InputError, match=r"outside the calibrated range \[-10, 10\] mm"):
        LayerTable.read(jp).characteristic_at(y)


def _corrupt(tmp_path, change):
    _, (jp, _) = _table(tmp_path)
    data = json.loads(jp.read_text())
    change(data)
    jp.write_text(json.dumps(data))
    return jp


@pytest.mark.parametrize("change,match", [
    (lambda d: d.update(format="other"), "'format' must be"),
    (lambda d: d.update(format_version=7), "unsupported format_version"),
    (lambda d: d["header"].update(body="axle"), "header.body"),
    (lambda d: d["positions"][1].update(y_mm=-20.0), "strictly increasing"),
    (lambda d: d["positions"][1]["k_N_per_mm3"].__setitem__(0, 1.0), "disagrees with the characteristic"),
    (lambda d: d["positions"][0]["characteristic"]["p_MPa"].__setitem__(3, 900.0), "position y = -10 mm"),
    (lambda d: d["positions"][0].pop("characteristic"), "missing 'characteristic'"),
    (lambda d: d.update(positions=[]), "no calibrated positions"),
])
def test_invalid_tables_are_rejected(tmp_path, change, match):
    jp = _corrupt(tmp_path, change)
    with pytest.raises(InputError, match=match):
        LayerTable.read(jp)


def test_truncated_or_missing_file(tmp_path):
    _, (jp, _) = _table(tmp_path)
    jp.write_text(jp.read_text()[:100])
    with pytest.raises(InputError, match="not a readable JSON layer table"):
        LayerTable.read(jp)
    with pytest.raises(InputError, match="not found"):
        LayerTable.read(tmp_path / "none.json")
    assert FORMAT == "wrlayer-layer-table"


def test_layer_table_does_not_import_the_fem_code():
    import subprocess
    import sys

    code = ("import sys, wrlayer.layer_table; "
            "bad = [m for m in sys.modules if m.startswith('calibration') or m in ('skfem', 'gmsh')]; "
            "print(bad); sys.exit(1 if bad else 0)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.returncode == 0, out.stdout + out.stderr


@pytest.mark.parametrize("name, model, y_range", [
    ("rail_60E1_default.json", "3d", (-35.9, 30.0)), ("wheel_S1002_default.json", "3d", (-45.0, 45.0)),
    ("rail_60E1_2d.json", "2d", (-35.9, 15.0)), ("wheel_S1002_2d.json", "2d", (-45.0, 30.0))])
def test_shipped_tables_are_valid_calibrations(name, model, y_range):
    """scenes/tables: valid, complete FEM calibrations; p_2 pinned at the FEM first yield; 3D dents below 2D.
    *_default: `make calibrate` (3D); *_2d: the former 2D default, kept for comparison."""
    from pathlib import Path

    path = Path(__file__).resolve().parents[3] / "scenes" / "tables" / name
    table = LayerTable.read(path)
    assert table.header["model"] == model and table.failed == []
    assert table.y_range_mm == pytest.approx(y_range)
    for pos in table.positions:
        assert pos["p2_MPa"] == pytest.approx(pos["first_yield_fem_MPa"], rel=0.03)
        assert pos["max_error_mm"] <= 0.02 * max(pos["fem_points"]["u_mm"])
    if model == "3d":
        assert table.header["config"] == "calibration/configs/default.toml"
        other = LayerTable.read(path.with_name(name.replace("_default", "_2d")))
        lo, hi = other.y_range_mm  # the 2D tables stop at the former range (rail +15, wheel +30 mm)
        for pos in (p for p in table.positions if lo <= p["y_mm"] <= hi):
            y = pos["y_mm"]
            u2 = other.characteristic_at(y).displacement(2.0 * pos["p2_MPa"])
            u3 = table.characteristic_at(y).displacement(2.0 * pos["p2_MPa"])
            assert u3 < u2


def test_characteristic_scales_with_the_patch_size(tmp_path):
    """Format 2: displacements scale with sqrt(a b) / sqrt(a_c b_c) (no length in the J2 half-space problem)."""
    t, (jp, _) = _table(tmp_path)
    r = LayerTable.read(jp)
    base = r.characteristic_at(0.0)
    same = r.characteristic_at(0.0, patch_mm=(7.0, 5.0))
    np.testing.assert_allclose(same.u_mm, base.u_mm)
    big = r.characteristic_at(0.0, patch_mm=(14.0, 10.0))  # twice the patch: twice the displacement, same p
    np.testing.assert_allclose(big.u_mm, 2.0 * base.u_mm)
    np.testing.assert_allclose(big.p_MPa, base.p_MPa)
    assert r.calibrated_length_mm(5.0) == pytest.approx(np.sqrt(35.0))
    with pytest.raises(InputError, match="patch_mm"):
        r.characteristic_at(0.0, patch_mm=(0.0, 5.0))


def test_version_1_tables_are_read_and_unscalable_without_semi_axes(tmp_path):
    t, (jp, _) = _table(tmp_path)
    data = json.loads(jp.read_text())
    assert data["format_version"] == 2
    data["format_version"] = 1
    for pos in data["positions"]:
        pos.pop("geometry")
    old = LayerTable.from_dict(data, "old.json")
    np.testing.assert_allclose(old.characteristic_at(0.0).u_mm, t.characteristics[1].u_mm)
    with pytest.raises(InputError, match="no calibrated semi-axes"):
        old.characteristic_at(0.0, patch_mm=(7.0, 5.0))


def _v4_table(rho=2.0, p_max=2400.0):
    from wrlayer.layer_table import LayerTable

    ch = {"u_mm": [0.0, 0.001, 0.01, 0.05], "p_MPa": [0.0, 800.0, 1400.0, 2400.0], "reverse_factor": rho}
    pos = [{"y_mm": y, "characteristic": ch, "geometry": {"a_mm": 5.0, "b_mm": 4.0}, "fit_mode": "operating_range",
            "calibrated_max_MPa": p_max + y,
            "levels_over_p2": [1.0, 2.0], "u_pl_error": [0.0, 0.01], "residual_error": [0.01]} for y in (0.0, 10.0)]
    return LayerTable({"body": "rail", "profile": "60E1"}, pos, [], "t.json")


def test_version_4_round_trip_reverse_factor_and_calibrated_range(tmp_path):
    from wrlayer.layer_table import LayerTable

    table = _v4_table()
    assert table.is_version_4 and table.to_dict()["format_version"] == 4
    back = LayerTable.read(table.write(tmp_path / "t.json", tmp_path / "t.csv")[0])
    assert back.characteristic_at(5.0).reverse_factor == pytest.approx(2.0)
    assert back.characteristic_at(5.0, patch_mm=(1.0, 1.0)).reverse_factor == pytest.approx(2.0)
    assert back.calibrated_max_MPa(5.0) == pytest.approx(2405.0)
    assert "reverse_factor" in (tmp_path / "t.csv").read_text().splitlines()[0]


def test_older_version_with_version_4_keys_is_refused():
    from wrlayer.layer_table import LayerTable

    data = _v4_table().to_dict()
    data["format_version"] = 3
    with pytest.raises(InputError, match="keys of format_version 4"):
        LayerTable.from_dict(data, "old.json")


def test_calibrated_range_of_an_older_table_is_its_largest_fem_point():
    from wrlayer.layer_table import LayerTable

    ch = {"u_mm": [0.0, 0.001, 0.01], "p_MPa": [0.0, 800.0, 1400.0]}
    pos = [{"y_mm": 0.0, "characteristic": ch, "fem_points": {"p_MPa": [0.0, 900.0, 2000.0], "u_mm": [0, 0, 0]}}]
    assert LayerTable({"body": "rail", "profile": "x"}, pos).calibrated_max_MPa(0.0) == 2000.0
    assert LayerTable({"body": "rail", "profile": "x"}, [{"y_mm": 0.0, "characteristic": ch}]).calibrated_max_MPa(
        0.0) is None


def test_a_contact_above_the_calibrated_range_is_an_error():
    from contact.layer.strip_lookup import check_coverage
    from wrlayer.errors import LayerRangeExceeded

    table = _v4_table(p_max=1500.0)
    check_coverage(table, np.array([1.0, 2.0]), "layers.rail", "rail", "t.json", p_peak_MPa=np.array([900.0, 1500.0]))
    with pytest.raises(LayerRangeExceeded, match=r"layers.rail: the rail table t.json at y = 2 mm is calibrated up "
                                                 r"to 1502 MPa; the contact's peak pressure there is 1700 MPa"):
        check_coverage(table, np.array([1.0, 2.0]), "layers.rail", "rail", "t.json",
                       p_peak_MPa=np.array([900.0, 1700.0]))


def test_an_older_table_gives_its_numbers_as_before():
    """A table of format 3 (the paper's fit) is read as it is: the paper's symmetric element (rho = 1), its
    characteristic unchanged, no refit."""
    from wrlayer.layer_table import LayerTable

    ch = {"u_mm": [0.0, 0.001, 0.01, 0.05], "p_MPa": [0.0, 800.0, 1400.0, 2400.0]}
    law = _v4_table().to_dict()  # only for the layout; the law itself is not needed
    data = {"format": law["format"], "format_version": 3, "header": {"body": "rail", "profile": "60E1"},
            "positions": [{"y_mm": 0.0, "characteristic": ch}]}
    table = LayerTable.from_dict(data, "old.json")
    c = table.characteristic_at(0.0)
    assert c.reverse_factor == 1.0 and c.u_mm.tolist() == ch["u_mm"] and c.p_MPa.tolist() == ch["p_MPa"]
    assert table.to_dict()["format_version"] == 2  # written back as the earlier format (no law, no version-4 keys)
