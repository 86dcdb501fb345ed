"""Denotations: the shortcuts (one goal row, products, gathers, scatters, shared closures) equal the definitions."""

import numpy as np
import pytest

from csql_sim.core.features.denotation import Denotations, by_definition
from csql_sim.core.features.formulation import load_formulation, primitive_arrays, support_arrays
from csql_sim.core.features.generate import generate_concepts
from csql_sim.core.features.grammar import parse
from csql_sim.core.features.move_features import literal_values, parse_literal
from csql_sim.core.state.moves import after, moves, pick_action
from csql_sim.core.state.state_count import sample_pairs
from csql_sim.core.state.world import State, successor


def tall(n: int) -> State:
    """One tower of n blocks, block 0 at the bottom."""
    return State((-1, *range(n - 1)))


def batches(form, rng):
    """(state, target) batches as the planner makes them: a state and the state after each move, one goal."""
    starts = [(s, g) for n in (7, 12) for s, g in sample_pairs(n, 6, rng) if s.held is None and g.held is None]
    starts.append((tall(14), State((-1,) * 14)))
    for start, goal in starts:
        states = [start] if not form.hand else [start, successor(start, pick_action(start, moves(start)[0].block))]
        for s in states:
            yield [s] + [after(s, m) for m in moves(s)], goal


@pytest.mark.parametrize("name", ["4op", "move"])
def test_every_generated_concept_and_role_equals_its_definition_with_the_goal_given_once(name):
    form = load_formulation(name)
    small = sample_pairs(4, 60, np.random.default_rng(0))
    prims, objects = primitive_arrays(form, [s for s, _ in small], [g for _, g in small])
    pool = generate_concepts(form, Denotations(prims, objects, form.constants), 6)
    nodes = [*pool.concepts, *pool.roles, parse("some(plus(inv(on)),clear)"), parse("all(star(inv(on_g)),clear)")]
    checked = 0
    for states, goal in batches(form, np.random.default_rng(1)):
        sup = np.array([s.support for s in states], np.int64)
        compact, objects = support_arrays(form, sup, np.array([goal.support], np.int64))
        full, _ = support_arrays(form, sup, np.tile(np.array(goal.support, np.int64), (len(states), 1)))
        assert compact["on_g"].shape[0] == 1 and full["on_g"].shape[0] == len(states)
        fast = Denotations(compact, objects, form.constants)
        for node in nodes:
            got, want = fast.of(node), by_definition(node, full, objects, form.constants)
            assert got.shape == want.shape and (got == want).all(), node.text()
            checked += 1
    assert checked > 1000


def test_literal_values_equal_the_definitions_on_towers():
    form = load_formulation("move")
    start = State((-1, *range(11), -1, *range(12, 17), -1, -1))  # towers of 12 and 6, two blocks on the table
    goal = State((-1, 0, 1, -1, 3, 4, *(-1,) * 14))
    literals = tuple(parse_literal(t) for t in ("x:all(star(on),eq(on,on_g))", "x':some(plus(inv(on)),clear)",
                                                 "down:some(on_g,all(star(inv(on)),on[1]))", "d:all(inv(on),on_g[1])",
                                                 "up:some(plus(on_g),not(clear))", "any:some(on,on_g[0])"))
    options, values = literal_values(literals, form, start, goal)
    states = [start] + [after(start, m) for m in options]
    full, objects = support_arrays(form, np.array([s.support for s in states], np.int64),
                                   np.tile(np.array(goal.support, np.int64), (len(states), 1)))
    for j, lit in enumerate(literals):
        c = by_definition(parse(lit.feature), full, objects, form.constants)
        for i, m in enumerate(options):
            d = m.onto if m.onto >= 0 else objects - 1  # the table is the move domain's last object
            want = {"x": c[0, m.block], "x'": c[i + 1, m.block], "d": c[0, d], "down": c[i + 1].sum() < c[0].sum(),
                    "up": c[i + 1].sum() > c[0].sum(), "any": c[0].any()}[lit.slot]
            assert values[i, j] == want, (lit.text(), m)
    assert len(options) == 4 * 4 - 2  # four clear blocks: each onto the three others, and the tops to the table


def test_chain_any_is_the_quantifier_over_the_built_closure_on_functional_roles_with_cycles():
    from csql_sim.core.features.denotation import chain_any, closure

    rng = np.random.default_rng(7)
    for _ in range(20):
        b, n = int(rng.integers(1, 5)), int(rng.integers(1, 30))
        succ = np.where(rng.random((b, n)) < 0.8, rng.integers(0, n, (b, n)), -1)  # any links: cycles and loops
        role = np.zeros((b, n, n), bool)
        rows, xs = np.nonzero(succ >= 0)
        role[rows, xs, succ[rows, xs]] = True
        c = rng.random((int(rng.choice([1, b])), n)) < 0.3
        plus = closure(role)
        star = plus | np.eye(n, dtype=bool)[None]
        for reflexive, built in ((False, plus), (True, star)):
            assert (chain_any(c, succ, reflexive) == (built & c[:, None, :]).any(axis=2)).all()
