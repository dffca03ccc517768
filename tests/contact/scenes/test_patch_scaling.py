"""A table layer with ``scale_to_patch = true`` is scaled to the contact solver's own patch
(fixed point over first-pass solves); the shipped 3D rail table at the crown."""

from pathlib import Path

import pytest

from wrlayer.layer_table import LayerTable
from contact.scenes.scene import load_scene
from contact.scenes.simulation import simulate
from wrlayer.errors import InputError

TABLE = Path(__file__).resolve().parents[3] / "scenes" / "tables" / "rail_60E1_default.json"
#: the crown scene both tests start from, up to the rail layer's keys
CROWN = """[load]
normal_force_N = 100000.0
rolling_radius_mm = 460.0
[material]
E_MPa = 210000.0
poisson = 0.3
[separation]
lateral_radius_mm = 300.0
half_width_mm = 25.0
[layers]
position_mm = {rail = 0.0}
"""


def _scene(tmp_path, extra: str, name: str):
    text = 'title = "crown, rail table layer"\n' + CROWN + f"""rail = "{TABLE}"
{extra}
[passes]
max = 1
[method]
alpha = 0.55
grid_mm = 0.1
"""
    path = tmp_path / f"{name}.toml"
    path.write_text(text)
    return load_scene(path)


def test_scaled_layer_follows_the_solved_patch(tmp_path):
    plain = simulate(_scene(tmp_path, "", "plain")).result
    scaled = simulate(_scene(tmp_path, "scale_to_patch = true", "scaled")).result
    assert plain.layer_scaled_to_patch is None
    info, first = scaled.layer_scaled_to_patch, scaled.passes[0]
    assert 2 <= info.solves <= 6
    # the layer was scaled to the patch the solver then found (fixed point, 0.1 %)
    assert info.a_mm == pytest.approx(first.length_mm / 2, rel=2e-3)
    assert info.b_mm == pytest.approx(first.width_mm / 2, rel=2e-3)
    # the crown's solved patch is larger than the calibrated one, so the scaled layer dents more (about the
    # length ratio; the layer's own compliance also enlarges the patch a little)
    geo = LayerTable.read(TABLE).positions[[p["y_mm"] for p in LayerTable.read(TABLE).positions].index(0.0)]["geometry"]
    ratio = (info.a_mm * info.b_mm / (geo["a_mm"] * geo["b_mm"])) ** 0.5
    assert ratio > 1.02
    assert first.up0_mm / plain.passes[0].up0_mm == pytest.approx(ratio, rel=0.05)
    # the records are plain data at the edge and come back equal
    assert type(scaled).from_dict(scaled.to_dict()) == scaled


def test_scale_to_patch_needs_a_table(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text('title = "bad"\n' + CROWN + """rail = {u_mm = [0.0, 0.01, 0.05], p_MPa = [0.0, 800.0, 1500.0]}
scale_to_patch = true
""")
    with pytest.raises(InputError, match="scale_to_patch.*only used with a calibration table"):
        load_scene(path)
