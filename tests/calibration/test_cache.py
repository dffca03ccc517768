"""Cache entries (calibration.cache) are read back through the typed from_dict of the result records: a valid
entry round-trips exactly; an entry of the wrong shape or kind (not JSON, a folder, a missing field, a string
where numbers belong, a NaN, another position's fit, a non-concave characteristic) is reported unusable, never
a traceback; writing the new entry replaces a folder in its place. No FEM."""

import dataclasses
import json

import numpy as np
import pytest

from calibration.cache import fem_entry, fit_entry, load_fit, load_indentation, save_entry
from calibration.hertz.geometry import given_geometry
from calibration.position_fit import fit_position
from calibration.results import IndentationResult, PositionFit
from calibration.settings import FitSettings
from meshes.profiles import get_profile

P = [0.0, 400.0, 800.0, 1000.0, 1200.0, 1600.0, 2000.0]
U_PL = [0.0, 0.0, 0.0, 0.002, 0.006, 0.02, 0.045]


def indentation(**kw) -> IndentationResult:
    c = 4e-5
    base = dict(model="3d", p_MPa=P, u_fem_mm=[c * p + u for p, u in zip(P, U_PL)], u_pl_mm=U_PL,
                first_yield_MPa=800.0, first_yield_anywhere_MPa=800.0, fem_elastic_compliance_mm_per_MPa=c,
                halfspace_compliance_mm_per_MPa=c, unload_peaks_MPa=[1200.0, 2000.0], residual_fem_mm=[0.006, 0.045],
                reverse_plasticity_mm=[0.0, 0.0], n_dofs=100, n_elements=20, newton_iterations=12, seconds=1.5)
    return IndentationResult(**dict(base, **kw))


@pytest.fixture(scope="module")
def fit() -> PositionFit:
    geo = given_geometry(get_profile("60E1"), 0.0, 7.0, 5.0)
    return fit_position(indentation(), geo, FitSettings(mode="paper", n_segments=3, max_relative_error=0.2), "test")


def test_valid_entries_round_trip(tmp_path, fit):
    ind = indentation(u_pl_depth_mm={"2": [0.0, 1.0]}, reference_depth_mm=3.0)
    save_entry(fem_entry(tmp_path, "a"), ind)
    back, why = load_indentation(fem_entry(tmp_path, "a"))
    assert why is None and back == ind
    save_entry(fit_entry(tmp_path, "b"), fit)
    back, why = load_fit(fit_entry(tmp_path, "b"), 0.0)
    assert why is None and back.to_dict() == fit.to_dict()
    assert json.loads(fit_entry(tmp_path, "b").read_text()) == json.loads(json.dumps(fit.to_dict()))


def _fem_variants():
    good = indentation().to_dict()
    return {"not json": "{", "empty": "{}", "list": "[]", "null": "null", "string list": '{"p_MPa": "many"}',
            "missing field": json.dumps({k: v for k, v in good.items() if k != "n_dofs"}),
            "unknown field": json.dumps(dict(good, extra=1)),
            "nan": json.dumps(dict(good, first_yield_MPa=float("nan"))),
            "nested list": json.dumps(dict(good, p_MPa=[[0.0], [1.0]])),
            "short": json.dumps(dict(good, p_MPa=[0.0], u_fem_mm=[0.0], u_pl_mm=[0.0])),
            "lengths": json.dumps(dict(good, u_pl_mm=good["u_pl_mm"][:-1])),
            "float count": json.dumps(dict(good, n_dofs=1.5)),
            "files": json.dumps(dict(good, files=[1])),
            "zero compliance": json.dumps(dict(good, halfspace_compliance_mm_per_MPa=0.0))}


@pytest.mark.parametrize("name", sorted(_fem_variants()))
def test_wrong_fem_entry_is_unusable(tmp_path, name):
    path = fem_entry(tmp_path, "x")
    path.write_text(_fem_variants()[name])
    entry, why = load_indentation(path)
    assert entry is None and why


def test_wrong_kind_entries_are_unusable_and_replaced(tmp_path, fit):
    folder = fem_entry(tmp_path, "x")
    (folder / "inside").mkdir(parents=True)
    assert load_indentation(folder) == (None, load_indentation(folder)[1]) and load_indentation(folder)[1]
    assert load_indentation(fem_entry(tmp_path, "absent"))[1] == "missing"
    save_entry(folder, indentation())  # the folder in the entry's place is replaced
    assert load_indentation(folder)[0] == indentation()
    (tmp_path / "bytes.json").write_bytes(b"\xff\xfe\x00")
    assert load_indentation(tmp_path / "bytes.json")[0] is None


def test_wrong_fit_entries_are_unusable(tmp_path, fit):
    good = fit.to_dict()
    concave_not = dict(good, characteristic={"u_mm": [0.0, 1.0, 1.5], "p_MPa": [0.0, 1.0, 3.0]})
    variants = [{}, dict(good, y_mm="0"), dict(good, fem_points={"u_mm": []}),
                dict(good, geometry=dict(good["geometry"], a_mm=None)), dict(good, fem={}), concave_not,
                dict(good, n_segments=True)]
    for k, data in enumerate(variants):
        path = fit_entry(tmp_path, str(k))
        path.write_text(json.dumps(data))
        assert load_fit(path, 0.0)[0] is None, k
    path = fit_entry(tmp_path, "other")
    path.write_text(json.dumps(good))
    assert load_fit(path, 0.0)[0] is not None
    entry, why = load_fit(path, 5.0)  # the fit of another position
    assert entry is None and "expected 5.0" in why


def test_fit_matches_the_points(fit):
    assert fit.n_segments == 3 and fit.p2_MPa == pytest.approx(800.0)
    assert np.max(np.abs(np.interp(fit.fem_points["p_MPa"], fit.characteristic["p_MPa"], fit.characteristic["u_mm"])
                         - fit.fem_points["u_mm"])) == pytest.approx(fit.max_error_mm, rel=1e-9)
    assert dataclasses.asdict(fit.fem)["model"] == "3d"
