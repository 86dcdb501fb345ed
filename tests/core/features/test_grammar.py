"""The feature grammar: generated within the bound, pruned, written and read back; well placed among its concepts."""

import itertools

import numpy as np
import pytest

from csql_sim.core.features.denotation import Denotations, closure
from csql_sim.core.features.formulation import load_formulation, primitive_arrays
from csql_sim.core.features.generate import generate_concepts
from csql_sim.core.features.grammar import GrammarError, parse
from csql_sim.core.state.goal_relations import well_placed
from csql_sim.core.state.world import all_states


def whole_space(name: str, n: int):
    """Every (state, goal) pair of n blocks the formulation has (hand-empty goals), as a batch."""
    form = load_formulation(name)
    states = [s for s in all_states(n) if form.hand or s.held is None]
    goals = [s for s in all_states(n) if s.held is None]
    pairs = list(itertools.product(states, goals))
    prims, objects = primitive_arrays(form, [s for s, _ in pairs], [g for _, g in pairs])
    return form, pairs, Denotations(prims, objects, form.constants)


@pytest.mark.parametrize("name", ["4op", "move"])
def test_the_grammar_generates_well_placed_within_the_bound(name):
    form, pairs, den = whole_space(name, 4)
    pool = generate_concepts(form, den, 6)  # within K = 8: the concept has complexity 6
    want = np.array([list(well_placed(s, g)) for s, g in pairs])
    empty = np.array([s.held is None for s, _ in pairs])
    found = [c for c in pool.concepts
             if (den.of(c)[empty][:, :4] == want[empty]).all()]
    assert found, "no generated concept is 'well placed' on every hand-empty pair of four blocks"
    assert found[0].complexity <= 6
    assert parse("all(star(on),eq(on,on_g))") in pool.concepts or found[0].complexity < 6


@pytest.mark.parametrize("name", ["4op", "move"])
def test_no_two_kept_concepts_agree_and_none_is_constant(name):
    form, pairs, den = whole_space(name, 3)
    pool = generate_concepts(form, den, 5)
    keys = {np.packbits(den.of(c)).tobytes() for c in pool.concepts}
    assert len(keys) == len(pool.concepts)
    for c in pool.concepts:
        value = den.of(c)
        assert value.any(axis=1).any() and not value.all(axis=1).all()
        assert c.complexity <= 5
    assert pool.duplicates > 0 and pool.candidates == pool.duplicates + len(pool.concepts) + len(pool.roles) \
        + pool.constant


def test_every_generated_concept_reads_back_from_its_text():
    form, _, den = whole_space("4op", 3)
    pool = generate_concepts(form, den, 6)
    for c in pool.concepts + pool.roles:
        assert parse(c.text(), c.is_role) == c


def test_complexity_counts_each_constructor_and_primitive():
    assert parse("all(star(on),eq(on,on_g))").complexity == 6
    assert parse("clear").complexity == 1
    assert parse("and(not(clear),some(inv(on),{table}))").complexity == 7
    assert parse("all(star(on),eq(on,on_g))").words() == "∀on*.(on = on_g)"


@pytest.mark.parametrize("text", ["", "and(clear)", "some(top,on)", "all(on,clear", "x y", "eq(on,top)",
                                  "not(on_g[2])", "some(on,clear))", "inv(top)"])
def test_a_malformed_expression_is_one_error(text):
    with pytest.raises(GrammarError):
        parse(text)


@pytest.mark.parametrize(("text", "named"), [("ontable", "ontable"), ("some(clear,top)", "clear"),
                                             ("eq(on,block)", "block"), ("{hand}", "hand")])
def test_a_name_the_domain_lacks_is_named_when_evaluated(text, named):
    form, _, den = whole_space("move", 3)
    with pytest.raises(GrammarError, match=named):
        den.of(parse(text))


def reachable(r: np.ndarray, x: int) -> set[int]:
    """The objects reachable from x in one relation (n, n) by one link or more, by search."""
    seen, frontier = set(), [y for y in range(len(r)) if r[x, y]]
    while frontier:
        y = frontier.pop()
        if y not in seen:
            seen.add(y)
            frontier += [z for z in range(len(r)) if r[y, z]]
    return seen


def test_closure_agrees_with_reachability_on_random_relations():
    rng = np.random.default_rng(3)
    for density in (0.1, 0.3):
        r = rng.random((20, 6, 6)) < density
        got = closure(r)
        for b in range(20):
            for x in range(6):
                assert {y for y in range(6) if got[b, x, y]} == reachable(r[b], x)


@pytest.mark.parametrize("n", [1, 2, 7, 40])
def test_closure_of_functional_relations_agrees_with_reachability(n):
    """Chains, cycles and objects without a successor; the relation and its inverse."""
    rng = np.random.default_rng(n)
    r = np.zeros((12, n, n), bool)
    for b in range(12):
        for x in range(n):
            if rng.random() < 0.8:
                r[b, x, int(rng.integers(n))] = True
    for rel in (r, r.transpose(0, 2, 1)):
        got = closure(rel)
        for b in range(12):
            for x in range(n):
                assert {y for y in range(n) if got[b, x, y]} == reachable(rel[b], x)
