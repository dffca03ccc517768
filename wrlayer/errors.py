"""The project's error types and the command-line guard that turns them into one-line messages.

Every package (meshes, calibration, contact) raises these, so that a command-line user sees
``error: <input>: <what is wrong>`` and a non-zero exit code instead of a traceback.

- :class:`InputError`: bad user input (a file, a key, a value). Exit code 2.
- :class:`ConvergenceError`: a numerical iteration failed (Newton, bracketing, ...). Exit code 3.
"""

from __future__ import annotations

import functools
import sys
from typing import Callable


class WrLayerError(Exception):
    """Base of the project's clear errors. ``str(err)`` is a complete one-line message."""

    exit_code = 1


class InputError(WrLayerError, ValueError):
    """Bad input: names the input (file, key or argument) and says what is wrong with it."""

    exit_code = 2

    def __init__(self, what: str, problem: str):
        self.what = what
        self.problem = problem
        super().__init__(f"{what}: {problem}")


class ConvergenceError(WrLayerError, ArithmeticError):
    """A numerical method did not converge or left its bracket; never returned as a result."""

    exit_code = 3


def cli_guard(main: Callable[..., int | None]) -> Callable[..., int]:
    """Wrap a command-line ``main``: project errors become ``error: ...`` on stderr and an exit code.

    Unexpected exceptions (programming errors) still propagate with their traceback.
    """

    @functools.wraps(main)
    def wrapped(*args, **kwargs) -> int:
        try:
            rc = main(*args, **kwargs)
        except WrLayerError as err:
            print(f"error: {err}", file=sys.stderr)
            return err.exit_code
        except KeyboardInterrupt:
            print("error: interrupted", file=sys.stderr)
            return 130
        return 0 if rc is None else int(rc)

    return wrapped


def require(condition: bool, what: str, problem: str) -> None:
    """Raise :class:`InputError` (what, problem) unless ``condition`` holds."""
    if not condition:
        raise InputError(what, problem)
