"""Calling a compiled kernel with the Python signal handlers held back (split from fast_engine)."""

from __future__ import annotations

import signal
import threading
from collections.abc import Callable
from typing import Any, TypeVar

HELD_SIGNALS = (signal.SIGINT, signal.SIGTERM)
"""The signals whose Python handlers :func:`call_kernel` holds back while a kernel is called."""
R = TypeVar("R")


class _Held:
    """Stands in for a Python signal handler during a kernel call: records the signal; once inactive, passes it on."""

    def __init__(self, handler: Callable[[int, Any], Any]) -> None:
        self.handler, self.signals, self.active = handler, [], True

    def __call__(self, signum: int, frame: Any) -> None:
        if self.active:
            self.signals.append(signum)
        else:  # left in place by an interrupted restore: behave as the handler
            self.handler(signum, frame)

    def __getattr__(self, name: str) -> Any:  # the handler's marks (e.g. the command line's after-fork test)
        if name == "handler":  # not set yet
            raise AttributeError(name)
        return getattr(self.handler, name)


def call_kernel(kernel: Callable[..., R], *args: Any) -> R:
    """``kernel(*args)`` with the Python handlers of SIGINT and SIGTERM run only once it has returned.

    Calling a kernel that takes a ``numpy.random.Generator`` runs Python code inside numba's
    unboxing of it (``ctypes.cast``), whose result numba does not check: a handler raising
    there (Ctrl-C's KeyboardInterrupt, the command line's Terminated) made it read through
    a NULL pointer, a segmentation fault. So for the call a stand-in that records the signal
    replaces each Python handler; a recorded signal is raised again once the handlers are
    back, and interrupts between two calls as before. Handlers run in the main thread only:
    elsewhere the kernel is called as it is.
    """
    if threading.current_thread() is not threading.main_thread():
        return kernel(*args)
    held: list[tuple[int, _Held]] = []
    try:
        for signum in HELD_SIGNALS:
            handler = signal.getsignal(signum)
            if callable(handler):  # not SIG_DFL, SIG_IGN or a handler set outside Python (None)
                held.append((signum, _Held(handler)))
                signal.signal(signum, held[-1][1])
        return kernel(*args)
    finally:
        for _, stand_in in held:
            stand_in.active = False
        for signum, stand_in in held:
            signal.signal(signum, stand_in.handler)
        for _, stand_in in held:
            for signum in stand_in.signals:
                signal.raise_signal(signum)
