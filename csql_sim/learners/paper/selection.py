"""Action selection from candidate values, driven by uniforms the caller draws.

Both functions take a uniform ``u`` in [0, 1) instead of a generator, so the trial loop
can draw uniforms in batches from one ``numpy.random.Generator`` (deterministic, fast).
"""

from __future__ import annotations

from collections.abc import Sequence
from math import exp


def boltzmann(values: Sequence[float], temperature: float, u: float) -> int:
    """Index drawn with P(i) = exp(v_i / T) / sum_l exp(v_l / T) (eq. 3).

    ``temperature <= 0`` is the greedy limit: the first index of the largest value.
    """
    top = max(values)
    if temperature <= 0.0:
        return values.index(top) if isinstance(values, list) else list(values).index(top)
    return _draw([exp((v - top) / temperature) for v in values], u)


def roulette(values: Sequence[float], u: float) -> int:
    """Index drawn with P(i) = v_i / sum_l v_l, the classifier systems' roulette wheel.

    Non-positive values get no share; if all are non-positive the draw is uniform.
    """
    shares = [v if v > 0.0 else 0.0 for v in values]
    total = sum(shares)
    if total <= 0.0:
        return min(int(u * len(values)), len(values) - 1)
    return _draw(shares, u, total)


def _draw(weights: list[float], u: float, total: float | None = None) -> int:
    """The index whose cumulative weight first exceeds ``u`` times the total weight."""
    x = u * (sum(weights) if total is None else total)
    acc = 0.0
    for i, w in enumerate(weights):
        acc += w
        if x < acc:
            return i
    return len(weights) - 1
