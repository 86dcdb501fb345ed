import math

import pytest

from csql_sim.learners.paper.selection import boltzmann, roulette

GRID = [(k + 0.5) / 20000 for k in range(20000)]


def frequencies(pick, count):
    hits = [0] * count
    for u in GRID:
        hits[pick(u)] += 1
    return [h / len(GRID) for h in hits]


def test_boltzmann_matches_eq3():
    values, temperature = [0.2, 0.5, 0.45], 0.1
    weights = [math.exp(v / temperature) for v in values]
    expected = [w / sum(weights) for w in weights]
    got = frequencies(lambda u: boltzmann(values, temperature, u), 3)
    assert got == pytest.approx(expected, abs=1e-3)


def test_boltzmann_zero_temperature_is_greedy_first_max():
    assert boltzmann([0.1, 0.7, 0.7], 0.0, 0.99) == 1


def test_boltzmann_tiny_temperature_has_no_overflow():
    assert boltzmann([0.0, 1.0], 1e-9, 0.0) == 1


def test_roulette_proportional_to_strength():
    values = [0.1, 0.3, 0.6]
    assert frequencies(lambda u: roulette(values, u), 3) == pytest.approx(values, abs=1e-3)


def test_roulette_ignores_non_positive_and_falls_back_to_uniform():
    assert frequencies(lambda u: roulette([0.0, -1.0, 2.0], u), 3) == pytest.approx([0, 0, 1])
    assert frequencies(lambda u: roulette([0.0, 0.0], u), 2) == pytest.approx([0.5, 0.5])
