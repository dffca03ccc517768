"""[passes] memory: the rolling law by default for table layers, the paper's relaxed rule when asked, bad values
refused with one line (exit 2)."""

from pathlib import Path

import numpy as np
import pytest

from contact.__main__ import main
from contact.passes.passes import run_passes
from contact.passes.rolling_memory import patch_semi_axes
from contact.scenes.scene import load_scene
from contact.scenes.scene_layers import build_layers
from contact.scenes.simulation import simulate
from wrlayer.errors import InputError

SCENES = Path(__file__).resolve().parents[3] / "scenes"


def calibrated_scene(tmp_path: Path, passes: str) -> Path:
    """scenes/calibrated_layers.toml with its [passes] replaced (tables by absolute path, not scaled to the
    patch so that the layers are the tables' characteristics)."""
    text = (SCENES / "calibrated_layers.toml").read_text(encoding="utf-8")
    text = text.replace('= "tables/', f'= "{SCENES / "tables"}/')
    text = text.replace("scale_to_patch = true", "scale_to_patch = false")
    head, _, tail = text.partition("[passes]")
    tail = tail[tail.index("\n[method]"):]
    path = tmp_path / "scene.toml"
    path.write_text(f"{head}[passes]\n{passes}\n{tail}", encoding="utf-8")
    return path


def test_rolling_residual_is_the_laws_prediction(tmp_path):
    """Under the default memory each pass's residual per strip is law.next_residual(U, r(p), p / p_2, c, a/b, s),
    with r(p) the static residual of a virgin element at the pass's peak pressure p (for a nonzero traction too), a/b
    the shape of the pass's contact region and s = b / (2 R) its convexity on the body (1/R the table's lateral
    curvature at the strip; the shipped laws have patch-shape and convexity nodes)."""
    scene = load_scene(calibrated_scene(tmp_path, "max = 3\ntraction_coefficient = 0.1"))
    assert scene.passes.memory == "rolling" and scene.passes.options.rule == "rolling"
    prob = scene.normal_problem()
    layers = build_layers(scene, prob.strip_y_mm)
    bodies = layers.bodies()
    assert set(bodies) == {"rail", "wheel"}
    assert all(lay.rolling_law is not None for lay in bodies.values())
    solutions = []
    records, _ = run_passes(prob, layers, scene.passes.options, method=scene.method.normal_method(),
                            on_pass=lambda rec, sol: solutions.append(sol))
    assert len(records) == 3
    accumulated = {name: np.zeros(prob.strip_y_mm.size) for name in bodies}
    for rec, sol in zip(records, solutions):
        a_mm, b_mm = patch_semi_axes(sol, prob.grid_mm)  # the law's patch shape: the pass's contact region
        aspect = np.divide(a_mm, b_mm, out=np.ones_like(a_mm), where=b_mm > 0)
        virgin = layers.copy().bodies()
        for name, lay in virgin.items():
            assert lay.n_points == prob.strip_y_mm.size  # one element per strip
            before = lay.u_mm.copy()
            lay.load_to(rec.p_peak_MPa)
            static = lay.unload() - before
            p2 = lay.relaxed().yield_pressure_MPa()
            assert np.any(lay.lateral_curvature_per_mm != 0.0) and lay.rolling_law.convexity is not None
            expected = lay.rolling_law.next_residual(accumulated[name], np.maximum(static, 0.0),
                                                     rec.p_peak_MPa / p2, 0.1, aspect,
                                                     0.5 * b_mm * lay.lateral_curvature_per_mm)
            got = rec.cumulative_residual_mm[name]
            assert np.max(np.abs(got - expected)) <= 1e-12 * max(1.0, np.max(np.abs(expected)))
            accumulated[name] = expected
    assert np.max(accumulated["rail"]) > 1e-4  # the law was applied to a real dent


def test_relaxed_memory_keeps_the_static_residual(tmp_path):
    """memory = "relaxed" adds the virgin element's static residual every pass (the paper's model), which the
    rolling law does not."""
    runs = {}
    for memory in ("relaxed", "rolling"):
        scene = load_scene(calibrated_scene(tmp_path, f'max = 1\nmemory = "{memory}"'))
        prob = scene.normal_problem()
        layers = build_layers(scene, prob.strip_y_mm)
        runs[memory] = run_passes(prob, layers, scene.passes.options, method=scene.method.normal_method())[0][0]
    relaxed, rolling = runs["relaxed"], runs["rolling"]
    np.testing.assert_array_equal(relaxed.p_peak_MPa, rolling.p_peak_MPa)  # the same first normal solve
    virgin = build_layers(load_scene(tmp_path / "scene.toml"), load_scene(tmp_path / "scene.toml").normal_problem()
                          .strip_y_mm).bodies()["rail"]
    before = virgin.u_mm.copy()
    virgin.load_to(relaxed.p_peak_MPa)
    np.testing.assert_array_equal(relaxed.cumulative_residual_mm["rail"], virgin.unload() - before)
    assert not np.allclose(relaxed.cumulative_residual_mm["rail"], rolling.cumulative_residual_mm["rail"])


@pytest.mark.parametrize("name", ["paper_shakedown.toml", "paper_with_layer.toml"])
def test_paper_scenes_say_relaxed(name):
    scene = load_scene(SCENES / name)
    assert scene.passes.memory == "relaxed" and scene.passes.options.rule == "relaxed"


def test_paper_shakedown_numbers_unchanged():
    """The paper's shakedown scene (relaxed) keeps its numbers: 20 passes at 1e-4 mm, last p_max near p_2 (the
    values before the rolling law existed)."""
    passes = simulate(load_scene(SCENES / "paper_shakedown.toml")).result.passes
    assert len(passes) == 20
    assert passes[-1].p_max_MPa == pytest.approx(1194.2050879354497, rel=1e-9)
    assert passes[-1].up0_mm == pytest.approx(8.694284333092897e-05, rel=1e-6)


def test_hardening_is_state_kept(tmp_path):
    scene = load_scene(calibrated_scene(tmp_path, "max = 2\nhardening = true"))
    assert scene.passes.memory == "state_kept" and scene.passes.hardening
    scene = load_scene(calibrated_scene(tmp_path, 'max = 2\nmemory = "state_kept"'))
    assert scene.passes.hardening and scene.passes.options.rule == "state_kept"
    scene = load_scene(calibrated_scene(tmp_path, 'max = 2\nmemory = "state_kept"\nhardening = true'))
    assert scene.passes.options.rule == "state_kept"


@pytest.mark.parametrize("passes, key", [
    ('memory = "sticky"', "passes.memory"),
    ("memory = 3", "passes.memory"),
    ('memory = "relaxed"\nhardening = true', "passes.memory"),
    ('memory = "state_kept"\nhardening = false', "passes.memory"),
    ("traction_coefficient = 1.5", "passes.traction_coefficient"),
    ('traction_coefficient = "high"', "passes.traction_coefficient"),
])
def test_bad_memory_is_one_line_exit_2(tmp_path, capsys, passes, key):
    path = calibrated_scene(tmp_path, f"max = 2\n{passes}")
    with pytest.raises(InputError):
        load_scene(path)
    out = tmp_path / "out"
    rc = main(["simulate", str(path), "--out", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2
    assert len(err) == 1 and err[0].startswith("error: ") and key in err[0], err
    assert not out.exists() or not any(out.iterdir())
