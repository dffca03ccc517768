"""In wheel-rail scenes ``scale_to_patch`` scales each patch's table characteristics to that
patch's own solved semi-axes (fixed point), per patch when a wheel has two; scene key validation and result keys."""

import json
from pathlib import Path

import pytest

from wrlayer.layer_table import LayerTable
from contact.layer.patch_scaling import PATCH_SCALING_TOLERANCE
from contact.wheel_rail.parse import parse_wheel_rail_scene
from contact.run_files import run_wheel_rail_scene
from contact.scenes.layers import LayerSources
from contact.wheel_rail.inputs import WheelRailInputs
from contact.wheel_rail.sections import WheelLoadSpec, WheelRailMethodSpec
from contact.wheel_rail.solve import solve_wheel
from contact.wheel_rail.track_geometry import WheelsetPose
from wrlayer.errors import InputError

#: These cases' F_Z is continuous at the balance: the iteration meets 1e-8 of Q (the accepted limit is wider only
#: where F_Z jumps across Q).
CONTINUOUS_BALANCE = 1e-6

TABLES = Path(__file__).resolve().parents[3] / "scenes" / "tables"


def _run(data, scene_path, out_dir, plots=False):
    return run_wheel_rail_scene(parse_wheel_rail_scene(data, scene_path), out_dir, plots).to_dict()


class _Recording:
    """A LayerTable that records the patch sizes it is asked for."""

    def __init__(self, table: LayerTable):
        self.table, self.asked = table, []

    @property
    def y_range_mm(self):
        return self.table.y_range_mm

    @property
    def rolling_law(self):
        return self.table.rolling_law

    def calibrated_max_MPa(self, y_mm):
        return self.table.calibrated_max_MPa(y_mm)

    def lateral_curvature_at(self, y_mm):
        return self.table.lateral_curvature_at(y_mm)

    def characteristic_at(self, y_mm, patch_mm=None):
        self.asked.append(patch_mm)
        return self.table.characteristic_at(y_mm, patch_mm=patch_mm)


@pytest.fixture(scope="module")
def tables():
    return LayerTable.read(TABLES / "rail_60E1_default.json"), LayerTable.read(TABLES / "wheel_S1002_default.json")


def test_each_patch_is_scaled_to_its_own_size(rail60, s1002, placed, tables):
    rail_t, wheel_t = (_Recording(t) for t in tables)
    inputs = WheelRailInputs(pose=WheelsetPose(5.2), load=WheelLoadSpec(vertical_load_N=50000.0),
                             method=WheelRailMethodSpec(normal="kik_piotrowski"))   # two patches (exact: merged)
    sol = solve_wheel(rail60, s1002, inputs, LayerSources(rail=rail_t, wheel=wheel_t, scale_to_patch=True),
                      placed_rail=placed)
    assert len(sol.patches) == 2  # tread and flange root: two patches of different size
    assert abs(sum(p.vertical_N for p in sol.patches) - 50000.0) / 50000.0 < CONTINUOUS_BALANCE
    sizes = []
    for p in sol.patches:
        a, b = p.layer_patch_mm
        assert p.layer_scaling_solves >= 2
        # fixed point: the layers were scaled to the patch they produced
        assert a == pytest.approx(0.5 * p.normal.length_mm, rel=2 * PATCH_SCALING_TOLERANCE)
        assert b == pytest.approx(0.5 * p.normal.width_mm, rel=2 * PATCH_SCALING_TOLERANCE)
        assert (a, b) in rail_t.asked and (a, b) in wheel_t.asked
        sizes.append((a, b))
    assert sizes[0] != pytest.approx(sizes[1], rel=0.1)
    # a patch smaller than the calibrated one gets a smaller residual than the unscaled layer at the flange root
    plain = solve_wheel(rail60, s1002, inputs, LayerSources(rail=tables[0], wheel=tables[1]), placed_rail=placed)
    assert plain.patches[0].layer_patch_mm is None and plain.patches[0].layer_scaling_solves == 0
    flange = max(sol.patches, key=lambda p: p.normal.p_max_MPa)
    flange_plain = max(plain.patches, key=lambda p: p.normal.p_max_MPa)
    a, b = flange.layer_patch_mm
    if (a * b) ** 0.5 < tables[0].calibrated_length_mm(flange.candidate.y_rail_mm):
        assert flange.residual_mm["rail"].max() < flange_plain.residual_mm["rail"].max()
    else:
        assert flange.residual_mm["rail"].max() > flange_plain.residual_mm["rail"].max()


def test_scale_to_patch_with_a_combined_layer_is_refused(tmp_path):
    data = {"type": "wheel_rail", "layers": {"combined": {"u_mm": [0.0, 0.01], "p_MPa": [0.0, 500.0]},
                                             "scale_to_patch": True}}
    with pytest.raises(InputError, match=r"layers.scale_to_patch: only used with calibration tables"):
        parse_wheel_rail_scene(data, tmp_path / "s.toml")
    with pytest.raises(InputError, match="scale_to_patch"):
        LayerSources(combined=object(), scale_to_patch=True)


def test_scene_records_the_scaled_patch(tmp_path):
    data = {"type": "wheel_rail", "wheel": {"side": "right"}, "load": {"vertical_load_N": 20000.0},
            "wheelset": {"lateral_mm": 7.0},
            "layers": {"rail": str(TABLES / "rail_60E1_default.json"), "wheel": str(TABLES / "wheel_S1002_default.json"),
                       "scale_to_patch": True},
            "output": {"deformed_profiles": False}}
    result = _run(data, tmp_path / "s.toml", tmp_path / "out", plots=False)
    patch = result["cases"][0]["wheels"]["right"]["patches"][0]
    scaled = patch["layer_scaled_to_patch"]
    assert scaled["a_mm"] == pytest.approx(0.5 * patch["length_mm"], rel=2 * PATCH_SCALING_TOLERANCE)
    assert scaled["b_mm"] == pytest.approx(0.5 * patch["width_mm"], rel=2 * PATCH_SCALING_TOLERANCE)
    assert scaled["balances"] >= 1
    json.dumps(result)

