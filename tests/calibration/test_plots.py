"""rail_parameters.png / wheel_parameters.png: every segment's curve with its own line style and marker, the
legends beside the panels (not over k_1)."""

from pathlib import Path

import matplotlib.pyplot as plt

from calibration.plots import parameters_figure
from wrlayer.layer_table import LayerTable

TABLES = Path(__file__).resolve().parents[2] / "scenes" / "tables"


def test_parameter_curves_distinct_and_legends_outside():
    table = LayerTable.read(TABLES / "rail_60E1_default.json")
    fig = parameters_figure(table)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    k_axis, t_axis = fig.axes
    n = max(ch.n_segments for ch in table.characteristics)
    assert len(k_axis.get_lines()) == n and len(t_axis.get_lines()) == n - 1
    for ax in (k_axis, t_axis):
        styles = [(str(line.get_linestyle()), line.get_marker()) for line in ax.get_lines()]
        assert len(set(styles)) == len(styles)                           # k_3 and k_5 no longer alike
        assert len({line.get_marker() for line in ax.get_lines()}) == len(styles)
        legend = ax.get_legend()
        assert legend.get_window_extent(renderer).x0 >= ax.get_window_extent(renderer).x1
    plt.close(fig)
