"""Wheel-rail pictures: the sweep title names the scene file and the normal method; the residual displacements
use a colour bar (not one legend entry per case) and show only where there are residual displacements."""

from types import SimpleNamespace as Record

import matplotlib.pyplot as plt
import numpy as np
import pytest

from contact.wheel_rail.plots import (RESIDUAL_FRACTION, RESIDUAL_MARGIN_MM, ResidualCurve, residual_figure,
                                      residual_span, sweep_title)


def test_sweep_title_names_scene_file_and_normal_method():
    def result(normal):
        return {"title": "A-2.2", "scene_file": "/x/manchester_a22.toml",
                "method": {"normal": normal, "alpha": 0.55, "grid_mm": 0.1, "exact_cells": 64,
                           "contact_point": "weighted_centre"}}

    kp, exact = sweep_title(result("kik_piotrowski")), sweep_title(result("exact"))
    assert kp != exact
    assert "manchester_a22.toml" in kp and "Kik–Piotrowski" in kp and "weighted centre" in kp
    assert "exact half-space solver (64 cells along x)" in exact     # elastic scene: no layer mode


def test_residual_displacements_colour_bar_and_limits():
    y = np.linspace(-60.0, 40.0, 1001)
    curves = []
    for k, lateral in enumerate(np.arange(2.0, 10.5, 0.5)):            # 17 cases, as in the layered sweep
        bump = 10.0 * np.exp(-((y + 35.0 + 0.2 * k) / 0.3) ** 2)
        curves += [ResidualCurve("rail", "right", lateral, y, bump),
                   ResidualCurve("wheel", "left" if k % 2 else "right", lateral, y, 0.5 * bump)]
    fig = residual_figure(curves, "wheelset lateral displacement (mm)")
    rail, wheel, bar = fig.axes
    assert bar.get_ylabel() == "wheelset lateral displacement (mm)"
    assert bar.get_ylim() == pytest.approx((2.0, 10.0))
    assert [t.get_text() for t in rail.get_legend().get_texts()] == ["right wheel"]
    assert [t.get_text() for t in wheel.get_legend().get_texts()] == ["right wheel", "left wheel"]
    lo, hi = rail.get_xlim()
    assert (lo, hi) == pytest.approx(residual_span([c for c in curves if c.body == "rail"]))
    above = np.concatenate([c.y_mm[c.up_um > RESIDUAL_FRACTION * 10.0] for c in curves if c.body == "rail"])
    assert lo == pytest.approx(above.min() - RESIDUAL_MARGIN_MM) and hi == pytest.approx(above.max()
                                                                                         + RESIDUAL_MARGIN_MM)
    assert hi - lo < 15.0                                                # not the whole profile (100 mm)
    plt.close(fig)


def test_sweep_panels_name_their_frame_and_one_legend_is_below_them(monkeypatch, tmp_path):
    """sweep.png: every panel titled with what it shows per patch or per wheel and in which frame; the contact-frame
    creep forces and the track-frame Y and Y/Q never share a panel; one legend (the wheels) below the panels."""
    from contact.wheel_rail import plots

    kept = []
    monkeypatch.setattr(plots, "save_figure", lambda fig, path: kept.append(fig))
    patch = {"y_rail_mm": -1.0, "contact_angle_rad": 0.01, "normal_force_N": 1e4, "p_max_MPa": 900.0,
             "Fx_N": 100.0, "Fy_N": -50.0, "normal_track": (0.0, 0.1, 0.99)}
    cases = [Record(lateral_mm=lat, error=None,
                    wheels={side: Record(patches=[Record(**patch)], Y_over_Q=0.1,
                                         force_on_wheel_track_N=(100.0, 1000.0, 1e4)) for side in ("right", "left")})
             for lat in (0.0, 1.0, 2.0)]
    plots._sweep_plot(Record(inputs={"title": "t"}, cases=cases), tmp_path / "s.png")
    (fig,) = kept
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    titles = [ax.get_title() for ax in fig.axes]
    assert len(titles) == 8 and all(t.startswith(("per patch", "per wheel")) for t in titles)
    contact = [ax for ax in fig.axes if "contact frame" in ax.get_title()]
    track = [ax for ax in fig.axes if "track frame" in ax.get_title()]
    assert [ax.get_ylabel() for ax in contact] == ["F_x on the wheel (kN)", "F_y on the wheel (kN)"]
    assert [ax.get_ylabel() for ax in track] == ["Y on the wheel (kN)", "Y/Q (-)"]
    assert track[0].lines[0].get_ydata()[0] == 1.0 and track[1].lines[0].get_ydata()[0] == 0.1
    assert all(ax.get_legend() is None for ax in fig.axes)
    (legend,) = fig.legends
    assert [t.get_text() for t in legend.get_texts()] == ["left wheel", "right wheel"]
    assert legend.get_window_extent(renderer).y1 <= min(ax.get_window_extent(renderer).y0 for ax in fig.axes)
    plt.close(fig)
