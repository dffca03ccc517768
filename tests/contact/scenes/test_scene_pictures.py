"""Scene pictures: the Hertz ellipse on the patch of a scene with a Hertz reference, the separation legends beside
(never over) the curves."""

from pathlib import Path

import matplotlib.pyplot as plt
import pytest
from matplotlib.patches import Ellipse

from contact.scenes import plots
from contact.scenes.scene import load_scene
from contact.scenes.simulation import simulate

SCENES = Path(__file__).resolve().parents[3] / "scenes"


@pytest.fixture
def figures(monkeypatch):
    """The figures the picture functions save (kept open instead of written)."""
    kept = []
    monkeypatch.setattr(plots, "save_figure", lambda fig, path: kept.append(fig))
    yield kept
    for fig in kept:
        plt.close(fig)


def ellipses(fig):
    return [p for ax in fig.axes for p in ax.patches if isinstance(p, Ellipse)]


def test_hertz_ellipse_drawn_only_for_a_hertz_reference(figures, tmp_path):
    hertz = load_scene(SCENES / "hertz_check.toml")
    assert plots.hertz_semi_axes(hertz) == pytest.approx((11.2209 / 2, 4.6798 / 2))
    assert plots.hertz_semi_axes(load_scene(SCENES / "paper_no_layer.toml")) is None  # paper Table 1: no ellipse
    plots.write_scene_plots(simulate(hertz), tmp_path)
    (patch,) = [f for f in figures if f.axes[0].get_aspect() == 1.0 and ellipses(f)]
    (ellipse,) = ellipses(patch)
    assert (ellipse.width, ellipse.height) == pytest.approx((11.2209, 4.6798))
    assert "Hertz ellipse" in ellipse.get_label()


def test_exact_pressure_picture_has_the_hertz_ellipse(figures, tmp_path):
    plots.write_scene_plots(simulate(load_scene(SCENES / "hertz_check_exact.toml")), tmp_path)
    assert sum(len(ellipses(f)) for f in figures) == 2          # patch and exact pressure pictures


def test_separation_legends_beside_the_panels():
    run = simulate(load_scene(SCENES / "paper_with_layer.toml"))      # three panels (a layer: residuals)
    fig = plots.separation_figure(run)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    assert len(fig.axes) == 3
    for ax in fig.axes:
        legend, box = ax.get_legend(), ax.get_window_extent(renderer)
        assert legend is not None
        assert legend.get_window_extent(renderer).x0 >= box.x1     # right of the axes, not over the curves
    plt.close(fig)


def test_contour_labels_of_two_patches_do_not_overlap(figures, tmp_path):
    """patch_pass1.png of two_patches: the pressure labels sit apart on each patch's reference strip, inside the
    outline, upright; their boxes do not overlap once drawn."""
    run = simulate(load_scene(SCENES / "two_patches.toml"))
    plots.plot_patch(run.first, tmp_path / "p.png", "two patches")
    fig = figures[-1]
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    labels = [t for t in fig.axes[0].texts if t.get_text().isdigit()]
    assert len(labels) >= 6                                    # both patches labelled
    boxes = [t.get_window_extent(renderer) for t in labels]
    assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1:])
    assert all(t.get_rotation() == 0 for t in labels)


def test_label_positions_keep_a_gap_and_stay_inside_the_patch():
    import numpy as np

    x = np.linspace(-10.0, 10.0, 401)
    p = 1500.0 * np.sqrt(np.clip(1.0 - (x / 6.0) ** 2, 0.0, None))   # a Hertz-like row, edge at 6 mm
    levels, where = plots.label_positions(x, p, [200, 400, 600, 800, 1000, 1200, 1400], 0.0, 0.8)
    xs = [w[0] for w in where]
    assert levels[0] == 1400 and levels == sorted(levels, reverse=True)
    assert all(b - a >= 0.8 for a, b in zip(xs, xs[1:])) and max(xs) <= 6.0 - 0.4
    assert 200 not in levels                                   # the crowded outer levels are left to the colour bar
