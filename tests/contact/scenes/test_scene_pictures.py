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
