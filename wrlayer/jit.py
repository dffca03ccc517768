"""Loop kernels compiled by numba only when the work pays for the compiler (tiered execution).

Importing numba and loading a cached kernel costs about 0.5 s of CPU, more than a small scene's whole solve (a
Hertz check takes about 0.1 s in plain Python). A kernel decorated with :func:`kernel` therefore runs as plain
Python until it has processed ``budget`` units of work in this process (the units are what ``size`` returns for a
call, e.g. the elements it loops over), and from then on as the numba-compiled function (``cache=True``). A
single call larger than the budget compiles at once. The Python and the compiled function are the same source, so
the formula is written once; both give the same numbers (no fastmath).

``WRLAYER_JIT`` overrides the rule: ``always`` (compile at the first call), ``never`` (plain Python), anything else
or unset: ``auto``. A kernel that calls another kernel is compiled with the compiled callee (numba needs the
dispatcher, not this wrapper, among the function's globals).
"""

from __future__ import annotations

import os
import types
from typing import Callable

#: Default work budget of a kernel in plain Python before it is compiled (units of its ``size``; about 0.05-0.2 s
#: of interpreted loops for the kernels of this project).
DEFAULT_BUDGET = 200_000


def jit_mode() -> str:
    """``always``, ``never`` or ``auto`` from ``WRLAYER_JIT``."""
    mode = os.environ.get("WRLAYER_JIT", "auto").strip().lower()
    return mode if mode in ("always", "never") else "auto"


class TieredKernel:
    """A loop kernel run as plain Python until its work budget is spent, then numba-compiled (see the module)."""

    def __init__(self, func: Callable, size: Callable[..., float] | None, budget: float, options: dict):
        self.py_func = func
        self.options = options
        self.size = size
        self.budget = budget
        self.spent = 0.0
        self._compiled = None
        self.__name__ = func.__name__
        self.__qualname__ = func.__qualname__
        self.__doc__ = func.__doc__
        self.__module__ = func.__module__

    def compiled(self):
        """The numba dispatcher of the kernel (compiled or loaded from numba's cache on first use)."""
        if self._compiled is None:
            import numba  # here: importing numba costs about 0.4 s, paid only once the work needs it
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
        if self._compiled is not None:
            return self._compiled(*args)
        mode = jit_mode()
        if mode == "never":
            return self.py_func(*args)
        work = float(self.size(*args)) if self.size is not None else 0.0
        if mode == "always" or self.budget <= 0 or self.spent + work > self.budget:
            return self.compiled()(*args)
        self.spent += work
        return self.py_func(*args)


def kernel(size: Callable[..., float] | None = None, budget: float = DEFAULT_BUDGET, **options) -> Callable:
    """Decorator: the function as a :class:`TieredKernel`; ``size(*args)`` is a call's work (None: no work of its
    own, for a helper kernel whose callers count it; it is compiled with its first compiled caller); ``options``
    go to ``numba.njit`` (a kernel with ``fastmath`` differs from its Python run in the last digits: give it
    ``budget=0``, compiled at the first call)."""
    def wrap(func: Callable) -> TieredKernel:
        return TieredKernel(func, size, budget, options)
    return wrap


__all__ = ["DEFAULT_BUDGET", "TieredKernel", "jit_mode", "kernel"]
