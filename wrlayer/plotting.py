"""Common settings of every picture the project writes (matplotlib): one resolution, unit labels, legends beside
the axes, atomic saving."""

from __future__ import annotations

import io
import os
from pathlib import Path

#: Resolution of every PNG written by the project (dots per inch).
DPI = 150
#: Micrometre label (the micro sign, not "um").
MICRO_M = "µm"


def outside_legend(ax, fontsize: float = 8):
    """The axes' legend right of it, its upper left corner beside the axes' top right: never over the curves
    (leave room for it: a wider figure with ``constrained_layout=True``). Returns the legend."""
    return ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, fontsize=fontsize)


def save_figure(fig, path: str | os.PathLike) -> Path:
    """Write a matplotlib figure as PNG at :data:`DPI` to ``path`` atomically (a failure leaves no partial file)
    and close it; returns the path."""
    import matplotlib.pyplot as plt

    from wrlayer.atomic_write import atomic_write_bytes

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=DPI)
    plt.close(fig)
    return atomic_write_bytes(Path(path), buf.getvalue())


__all__ = ["DPI", "MICRO_M", "outside_legend", "save_figure"]
