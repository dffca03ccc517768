"""The defaults of the contact-geometry analysis (mm), in a module of their own so that the command line builds
its parser (``wrlayer geometry --help``, every ``python -m contact`` command) without importing the solvers."""

from __future__ import annotations

#: Default lateral range (mm): one millimetre beyond EN 15302's largest amplitude (10 mm).
DEFAULT_LATERAL_MM = (-11.0, 11.0)

#: Default lateral step of a sweep (mm): small enough that the jump threshold (1 mm) separates jumps from the
#: fast but continuous travel of the contact point on a conformal tread.
DEFAULT_STEP_MM = 0.1

#: EN 15302's amplitude range of the conicity function (mm): 0.5 .. 10 mm.
DEFAULT_AMPLITUDES_MM = tuple(0.5 * k for k in range(1, 21))

#: Default contact-point travel per step (mm) above which the step is a jump.
DEFAULT_JUMP_MM = 1.0

__all__ = ["DEFAULT_AMPLITUDES_MM", "DEFAULT_JUMP_MM", "DEFAULT_LATERAL_MM", "DEFAULT_STEP_MM"]
