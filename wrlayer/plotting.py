"""Common settings of every picture the project writes (matplotlib): one resolution, unit labels, atomic saving."""

from __future__ import annotations

import io
import os
from pathlib import Path

#: Resolution of every PNG written by the project (dots per inch).
DPI = 150
#: Micrometre label (the micro sign, not "um").
MICRO_M = "µm"


def save_figure(fig, path: str | os.PathLike) -> Path:
    """Write a matplotlib figure as PNG at :data:`DPI` to ``path`` atomically (a failure leaves no partial file)
    and close it; returns the path."""
    import matplotlib.pyplot as plt

    from wrlayer.atomic_write import atomic_write_bytes

    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=DPI)
    plt.close(fig)
    return atomic_write_bytes(Path(path), buf.getvalue())


__all__ = ["DPI", "MICRO_M", "save_figure"]
