"""Parameter ranges: :class:`Bounds` and the ranges the learners' parameters share (re-exported by ``params``)."""

from __future__ import annotations

import math
import sys
from dataclasses import dataclass


@dataclass(frozen=True)
class Bounds:
    """A closed or open interval of finite values, printed as ``[0, 1]``, ``(0, 1]``, ``>= 1``."""

    low: float = -math.inf
    high: float = math.inf
    low_open: bool = False
    high_open: bool = False

    def __str__(self) -> str:
        if self.high == math.inf:
            if self.low == -math.inf:
                return "finite"
            return f"{'>' if self.low_open else '>='} {self.low:g}"
        return f"{'(' if self.low_open else '['}{self.low:g}, {self.high:g}{')' if self.high_open else ']'}"

    def contains(self, value: float) -> bool:
        """Whether ``value`` is finite and inside the interval (an integer too large for a float is not)."""
        if not isinstance(value, float | int) or abs(value) > sys.float_info.max or not math.isfinite(value):
            return False
        above = value > self.low if self.low_open else value >= self.low
        below = value < self.high if self.high_open else value <= self.high
        return above and below


POSITIVE = Bounds(0.0, low_open=True)
NON_NEGATIVE = Bounds(0.0)
UNIT = Bounds(0.0, 1.0)
UNIT_NO_ZERO = Bounds(0.0, 1.0, low_open=True)
FINITE = Bounds()
AT_LEAST_ONE = Bounds(1.0)
RATIO = Bounds(0.0, 1e6)
"""A cap per experienced step (``replay_ratio``): large enough to mean "no cap", small enough that
ratio x steps is an integer."""
