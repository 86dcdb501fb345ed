"""numba's ``njit`` with its on-disk cache where numba finds a place to write it, compiled in memory where not.

``njit(cache=True)`` keeps the compiled code beside the source (``__pycache__``) or, where that
folder is read-only, in the user's cache folder (``~/.cache/numba``, or ``NUMBA_CACHE_DIR``).
Where neither can be written (a read-only install run with a read-only home) numba refuses to
decorate the function at import. :func:`cached_njit` then compiles it without a cache:
every process compiles the kernels again (seconds), but the command runs.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any


def cached_njit(**options: Any) -> Callable[[Callable], Callable]:
    """``numba.njit(cache=True, **options)``, or ``numba.njit(**options)`` where no cache folder can be written."""

    def wrap(func: Callable) -> Callable:
        from numba import njit

        try:
            return njit(cache=True, **options)(func)
        except RuntimeError:  # numba found no writable cache location for this file
            return njit(**options)(func)

    return wrap


__all__ = ["cached_njit"]
