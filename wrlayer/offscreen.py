"""Off-screen pyvista/VTK rendering on machines without a display (CI, clusters).

VTK's default render window is the X one; without ``DISPLAY`` it logs "bad X server connection" and only then
falls back. :func:`offscreen_pyvista` picks the headless window class up front (EGL, else OSMesa, whichever
library is present) and returns pyvista with ``OFF_SCREEN`` set.
"""

from __future__ import annotations

import ctypes.util
import os


def _headless_window_class() -> str | None:
    if ctypes.util.find_library("EGL"):
        return "vtkEGLRenderWindow"
    if ctypes.util.find_library("OSMesa"):
        return "vtkOSOpenGLRenderWindow"
    return None


def offscreen_pyvista():
    """``import pyvista`` configured for off-screen rendering (no window is ever opened)."""
    if not os.environ.get("DISPLAY") and "VTK_DEFAULT_OPENGL_WINDOW" not in os.environ:
        window = _headless_window_class()
        if window is not None:
            os.environ["VTK_DEFAULT_OPENGL_WINDOW"] = window
    import pyvista

    pyvista.OFF_SCREEN = True
    return pyvista


__all__ = ["offscreen_pyvista"]
