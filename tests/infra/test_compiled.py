"""cached_njit: numba's on-disk cache where it can be written, compiled in memory where not."""

import pytest
from numba import njit

from csql_sim.infra.compiled import cached_njit


def from_source(text: str):
    """A function defined from a string: no file beside it, so numba has nowhere to cache it."""
    namespace: dict = {}
    exec(text, namespace)  # noqa: S102 - the test's own source
    return namespace["add"]


def test_a_function_numba_cannot_cache_is_compiled_in_memory():
    text = "def add(a, b):\n    return a + b\n"
    with pytest.raises(RuntimeError):  # the case handled: njit(cache=True) refuses it
        njit(cache=True)(from_source(text))
    add = cached_njit()(from_source(text))
    assert add(2, 3) == 5 and add(2.5, 1.0) == 3.5

