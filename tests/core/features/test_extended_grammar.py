"""Role composition, union, restriction, closures of composed roles, loops and counts, against brute force.

The brute force below evaluates each constructor's definition over Python sets of objects and
pairs, state by state: nothing of numpy's denotations is shared with it.
"""

import itertools

import numpy as np
import pytest

from csql_sim.core.features.denotation import Denotations
from csql_sim.core.features.formulation import load_formulation, primitive_arrays
from csql_sim.core.features.generate import BASE, EXTENDED, generate_concepts
from csql_sim.core.features.grammar import GrammarError, Node, parse
from csql_sim.core.state.goal_relations import deadlocked
from csql_sim.core.state.state_count import sample_pairs


def brute(node: Node, prims: dict, row: int, objects: int):
    """A node's denotation in one pair, as a set of objects (concept) or of pairs (role), from the definitions."""
    op, a = node.op, node.args
    every = range(objects)
    if op == "top":
        return set(every)
    if op == "pred":
        return {x for x in every if prims[a[0]][row, x]}
    if op == "role":
        return {(x, y) for x, y in itertools.product(every, every) if prims[a[0]][row, x, y]}
    if op == "proj":
        pairs = brute(Node("role", (a[0],)), prims, row, objects)
        return {p[a[1]] for p in pairs}
    sub = [brute(x, prims, row, objects) for x in a]
    if op == "not":
        return set(every) - sub[0]
    if op == "and":
        return sub[0] & sub[1]
    if op == "some":
        return {x for x in every if any((x, y) in sub[0] for y in sub[1])}
    if op == "all":
        return {x for x in every if all(y in sub[1] for (z, y) in sub[0] if z == x)}
    if op == "eq":
        return {x for x in every if {y for z, y in sub[0] if z == x} == {y for z, y in sub[1] if z == x}}
    if op == "self":
        return {x for x in every if (x, x) in sub[0]}
    if op == "inv":
        return {(y, x) for x, y in sub[0]}
    if op == "comp":
        return {(x, z) for x, y in sub[0] for w, z in sub[1] if y == w}
    if op == "or":
        return sub[0] | sub[1]
    if op == "restrict":
        return {(x, y) for x, y in sub[0] if y in sub[1]}
    out = set(sub[0])
    while True:  # plus, star: add (x, z) for (x, y), (y, z) until nothing changes
        more = out | {(x, z) for x, y in out for w, z in out if y == w}
        if more == out:
            break
        out = more
    return out | {(x, x) for x in every} if op == "star" else out


def as_set(value: np.ndarray, role: bool):
    if role:
        return {(int(x), int(y)) for x, y in zip(*np.nonzero(value), strict=True)}
    return set(np.nonzero(value)[0].tolist())


def read(text: str) -> Node:
    """A concept, or else a role."""
    try:
        return parse(text)
    except GrammarError:
        return parse(text, is_role=True)


WAITS = "or(inv(on),comp(on_g,inv(on)))"
"""b waits for the block on it and for the block on its goal support: two edges of the deadlock graph."""
MISPLACED = "not(all(star(on),eq(on,on_g)))"
DEADLOCK_GRAPH = f"restrict(or({WAITS},on_g),{MISPLACED})"
"""The deadlock graph: b waits for the block on it, the block on its goal support, and that support; misplaced ones."""
EXPRESSIONS = ["comp(on,on)", "comp(on_g,inv(on))", "plus(comp(on,on_g))", "star(comp(inv(on_g),on))",
               "restrict(on,clear)", "or(on,on_g)", "self(plus(comp(on_g,inv(on))))", f"self(plus({WAITS}))",
               f"some(plus({WAITS}),clear)", "all(restrict(plus(on),ontable),ontable)", "self(on)"]


@pytest.mark.parametrize("text", EXPRESSIONS)
def test_the_new_constructors_equal_their_definitions_on_small_states(text):
    form = load_formulation("4op")
    pairs = sample_pairs(5, 40, np.random.default_rng(3))
    prims, objects = primitive_arrays(form, [s for s, _ in pairs], [g for _, g in pairs])
    den, node = Denotations(prims, objects, form.constants), read(text)
    got, counts = den.of(node), den.count(node)
    for row in range(len(pairs)):
        want = brute(node, prims, row, objects)
        assert as_set(got[row], node.is_role) == want, (text, row)
        assert counts[row] == len(want)


def test_the_deadlock_graph_is_a_role_and_its_cycles_a_concept_of_the_grammar():
    """The blocks on a cycle of the deadlock graph written in the grammar are exactly the deadlocked ones."""
    form = load_formulation("4op")
    pairs = [(s, g) for s, g in sample_pairs(6, 300, np.random.default_rng(4)) if s.held is None and g.held is None]
    prims, objects = primitive_arrays(form, [s for s, _ in pairs], [g for _, g in pairs])
    node = parse(f"self(plus({DEADLOCK_GRAPH}))")
    cycle = Denotations(prims, objects, form.constants).of(node)
    found = 0
    for row, (s, g) in enumerate(pairs):
        stuck = deadlocked(s, g)
        assert set(stuck) == set(np.nonzero(cycle[row])[0].tolist()), (s.notation(), g.notation())
        found += bool(stuck)
    assert found > 20 and node.complexity == 19  # expressible; beyond the default bound K = 8


def test_composed_closures_parse_back_and_read_in_notation():
    node = parse(f"self(plus({WAITS}))")
    assert parse(node.text()) == node and node.complexity == 9
    assert node.words() == "∃(on⁻¹ ⊔ (on_g ∘ on⁻¹))⁺.Self"
    assert parse("restrict(on,clear)", is_role=True).words() == "on|clear"
    with pytest.raises(GrammarError):
        parse("comp(on,clear)")  # a concept where a role is expected


def test_the_extended_generator_keeps_the_base_and_adds_composed_roles_within_the_bound():
    form = load_formulation("4op")
    pairs = sample_pairs(4, 60, np.random.default_rng(0))
    prims, objects = primitive_arrays(form, [s for s, _ in pairs], [g for _, g in pairs])
    base = generate_concepts(form, Denotations(prims, objects, form.constants), 5, BASE)
    extended = generate_concepts(form, Denotations(prims, objects, form.constants), 5, EXTENDED)
    ops = {n.op for n in extended.roles} | {n.op for n in extended.concepts}
    assert {"comp", "or", "restrict"} <= ops
    assert all(n.complexity <= 5 for n in (*extended.concepts, *extended.roles))
    assert not {n.op for n in (*base.concepts, *base.roles)} & {"comp", "or", "restrict", "self"}
    assert len(extended.roles) > len(base.roles)
    with pytest.raises(ValueError, match="unknown constructors"):
        generate_concepts(form, Denotations(prims, objects, form.constants), 3, ("join",))


def test_a_closure_over_more_than_255_objects_is_not_lost_to_overflow():
    """A role with 256 paths between two objects: the product must not wrap to 0."""
    n = 258
    r = np.zeros((1, n, n), bool)
    r[0, 0, 1:257] = True
    r[0, 1:257, 257] = True
    prims = {"r": r}
    den = Denotations(prims, n)
    assert den.of(parse("comp(r,r)", is_role=True))[0, 0, 257]
    assert den.of(parse("plus(r)", is_role=True))[0, 0, 257]
