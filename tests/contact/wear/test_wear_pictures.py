"""depth_per_step.png: the abscissa limited to where the steps changed the profile (stated rule), one legend beside
the panels."""

import matplotlib.pyplot as plt
import numpy as np
import pytest

from contact.wear.loop import run_wear
from contact.wear.plots import CHANGED_FRACTION, CHANGED_MARGIN_MM, changed_range, depths_figure


def test_depth_per_step_zoomed_on_the_changed_part(make_scene):
    run = run_wear(make_scene(layers=None, wear={"distance_km": 20.0, "steps": 2, "inelastic": False}),
                   show_progress=False)
    fig = depths_figure(run)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    panels = [ax for ax in fig.axes if ax.get_title()]
    assert [ax.get_title() for ax in panels] == ["right wheel", "right rail"]
    for ax in panels:
        side, body = ax.get_title().split()
        grid = run.steps[0].bodies[side, body].grid.y_mm
        lo, hi = ax.get_xlim()
        span = changed_range(run, side, body)
        assert (lo, hi) == pytest.approx((max(span[0], grid.min()), min(span[1], grid.max())))
        for rec in run.steps:                                  # every point above the threshold is shown
            bs = rec.bodies[side, body]
            tot = bs.wear_mm + bs.inelastic_mm
            shown = bs.grid.y_mm[tot > CHANGED_FRACTION * tot.max()]
            assert lo <= shown.min() - CHANGED_MARGIN_MM + 1e-9 or lo == pytest.approx(grid.min())
            assert hi >= shown.max() + CHANGED_MARGIN_MM - 1e-9 or hi == pytest.approx(grid.max())
        assert hi - lo < 0.5 * (grid.max() - grid.min())       # a zoom, not the whole profile
        assert ax.get_legend() is None
    (legend,) = fig.legends
    assert legend.get_window_extent(renderer).x0 >= max(ax.get_window_extent(renderer).x1 for ax in panels)
    assert np.all([line.get_label().startswith("wear, step") for line in legend.get_lines()])
    plt.close(fig)
