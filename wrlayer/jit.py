"""Loop kernels compiled by numba, or run as plain Python for a run too small to pay for the compiler.

Importing numba and loading a cached kernel costs about 0.5 s of CPU, more than a small scene's whole solve (a
Hertz check takes about 0.02 s in plain Python). A kernel decorated with :func:`kernel` is compiled by numba
(``cache=True``) at its first call, unless the kernels run as plain Python: with ``WRLAYER_JIT=never``, or inside
:func:`run_mode` for a run whose estimated cost (compiled) is below :data:`SMALL_RUN_S`. The Python function and
the compiled one are the same source, so each formula is written once; they agree to round-off (the last digit
may differ: libm against LLVM's intrinsics).

The choice is made once per run from its inputs (the cost estimate), never from what the process ran before, so a
run gives the same numbers alone, in a batch and on worker processes (which inherit the choice through the
environment). ``WRLAYER_JIT=always`` compiles whatever the cost. A kernel that calls another kernel is compiled
with the compiled callee (numba needs the dispatcher, not this wrapper, among the function's globals).
"""

from __future__ import annotations

import contextlib
import os
import types
from typing import Callable, Iterator

#: A run whose estimated cost with compiled kernels is below this runs them as plain Python (s): plain Python
#: is 30-50 times slower per kernel call, so such a run takes well under numba's 0.5 s start-up.
SMALL_RUN_S = 0.01

ENV = "WRLAYER_JIT"


#: The mode :func:`run_mode` chose for the block being run (None outside one): read on every kernel call, so kept
#: here rather than parsed from the environment each time (a sweep makes thousands of kernel calls).
_block_mode: str | None = None


def jit_mode() -> str:
    """``always``, ``never`` or ``auto`` (unset or anything else) from ``WRLAYER_JIT`` (inside :func:`run_mode`:
    the block's choice, which it also wrote to the environment)."""
    if _block_mode is not None:
        return _block_mode
    mode = os.environ.get(ENV, "auto").strip().lower()
    return mode if mode in ("always", "never") else "auto"


@contextlib.contextmanager
def run_mode(estimated_seconds: float) -> Iterator[bool]:
    """Within the block the kernels run as plain Python when ``WRLAYER_JIT`` is unset (``auto``) and the run's
    estimated cost is below :data:`SMALL_RUN_S`; yields whether they do. Sets the environment, so worker
    processes started in the block make the same choice."""
    global _block_mode
    python = jit_mode() == "never" or (jit_mode() == "auto" and estimated_seconds < SMALL_RUN_S)
    before, outer = os.environ.get(ENV), _block_mode
    os.environ[ENV] = _block_mode = "never" if python else "always"
    try:
        yield python
    finally:
        _block_mode = outer
        if before is None:
            os.environ.pop(ENV, None)
        else:
            os.environ[ENV] = before


class TieredKernel:
    """A loop kernel: numba-compiled at its first call unless the kernels run as plain Python (see the module)."""

    def __init__(self, func: Callable, options: dict):
        self.py_func = func
        self.options = options
        self._compiled = None
        self.__name__ = func.__name__
        self.__qualname__ = func.__qualname__
        self.__doc__ = func.__doc__
        self.__module__ = func.__module__

    def compiled(self):
        """The numba dispatcher of the kernel (compiled or loaded from numba's cache on first use)."""
        if self._compiled is None:
            import numba  # here: importing numba costs about 0.4 s, paid only by a run that compiles
            func = self.py_func
            callees = {name: value.compiled() for name in func.__code__.co_names
                       if isinstance(value := func.__globals__.get(name), TieredKernel)}
            if callees:
                func = types.FunctionType(func.__code__, {**func.__globals__, **callees}, func.__name__,
                                          func.__defaults__, func.__closure__)
                func.__qualname__ = self.py_func.__qualname__
                func.__module__ = self.py_func.__module__
            self._compiled = numba.njit(cache=True, **self.options)(func)
        return self._compiled

    def __call__(self, *args):
        if jit_mode() == "never":
            return self.py_func(*args)
        return self.compiled()(*args)


def kernel(**options) -> Callable:
    """Decorator: the function as a :class:`TieredKernel`; ``options`` go to ``numba.njit`` (e.g. fastmath)."""
    def wrap(func: Callable) -> TieredKernel:
        return TieredKernel(func, options)
    return wrap


__all__ = ["ENV", "SMALL_RUN_S", "TieredKernel", "jit_mode", "kernel", "run_mode"]
