"""One tiny 3D gap case: the rolling FEM of an elliptic patch with mixed hardening and traction, its case file
(read back instead of recomputed), the law fitted to it and the gap row against the layer."""

import json

import numpy as np
import pytest

import calibration.rolling.gap_cases as gap_cases
from calibration.rolling.config import RollingMaterial, TrackMeshSettings, TrackSettings
from calibration.rolling.gap_cases import GapCase, GapCaseResult, GapPosition, run_case
from calibration.rolling.law_fit import fit_passes

TRACK = TrackSettings(length_factor=1.0, step_factor=0.5, n_passes=2, ramp_steps=1)
MESH = TrackMeshSettings(elements_per_semi_axis=1.5, order=1, size_factor=3.0, fine_depth_factor=1.0,
                         fine_width_factor=1.0)
MIXED = RollingMaterial(H_iso_MPa=10000.0, H_kin_MPa=10000.0)


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    out = tmp_path_factory.mktemp("gap")
    case = GapCase(GapPosition("tiny", "", 0.0, 1.3, 1.0, MIXED), 2.1, 0.2, n_passes=2)
    return case, out, run_case(case, out, track=TRACK, mesh=MESH)


def test_tiny_case_rolls_and_is_written(tiny):
    case, out, res = tiny
    assert res.failed == "" and len(res.groove_mm) == 2 and res.n_dofs < 3000
    assert 0.5 < res.groove_mm[0] / res.static_dent_mm < 1.5       # a groove of the static dent's order
    assert res.groove_mm[1] >= res.groove_mm[0] > 0
    assert res.static_p_MPa[-1] == pytest.approx(2.1 * res.p_y_MPa)
    data = json.loads((out / f"{case.key}.json").read_text())
    assert GapCaseResult.from_dict(data) == res


def test_a_present_case_is_read_not_recomputed(tiny, monkeypatch):
    case, out, res = tiny
    monkeypatch.setattr(gap_cases, "build_model", lambda *a: pytest.fail("recomputed"))
    assert run_case(case, out, track=TRACK, mesh=MESH) == res


def test_law_fitted_to_the_case_reproduces_it(tiny):
    _, _, res = tiny
    fit = fit_passes(res.groove_mm, res.static_dent_mm)
    np.testing.assert_allclose(fit.factors(2) * res.static_dent_mm, res.groove_mm, rtol=1e-9)
