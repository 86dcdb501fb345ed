"""Formulations read from PDDL: the predicates, under the domain's own names, and a state's atoms."""

import numpy as np
import pytest

from csql_sim.core.features.formulation import load_formulation, parse_formulation, primitive_arrays
from csql_sim.core.files.pddl_import import PddlImportError
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.world import TABLE


def test_the_move_formulation_loads_from_its_pddl():
    form = load_formulation("move")
    assert not form.hand and form.constants == ("table",)
    assert {(p.name, p.arity) for p in form.predicates} == {("on", 2), ("clear", 1), ("block", 1), ("on_g", 2)}


def test_the_four_operator_formulation_loads_from_its_pddl():
    form = load_formulation("4op")
    assert form.hand and form.constants == ()
    assert {p.name for p in form.predicates} == {"on", "ontable", "clear", "holding", "handempty", "on_g",
                                                 "ontable_g"}


def test_a_domain_spelling_its_predicates_otherwise_keeps_its_names(tmp_path):
    text = load_formulation.__globals__["asset_text"]("domains", "blocks-4op.pddl")
    text = text.replace("ontable", "on-table").replace("handempty", "arm-empty")
    path = tmp_path / "d.pddl"
    path.write_text(text)
    names = {p.name for p in load_formulation(str(path)).predicates}
    assert {"on-table", "arm-empty", "on-table_g"} <= names and "ontable" not in names


def test_a_domain_that_is_not_a_blocks_world_is_refused():
    text = "(define (domain d) (:predicates (at ?x ?y)) (:action go :parameters (?x ?y) :precondition (at ?x ?y) " \
           ":effect (not (at ?x ?y))))"
    with pytest.raises(PddlImportError):
        parse_formulation(text, "d.pddl")


@pytest.mark.parametrize("name", ["4op", "move"])
def test_atoms_are_the_state_read_in_the_domain_s_predicates(name):
    form = load_formulation(name)
    state, goal = parse_config("BA,C"), parse_config("ABC")
    prims, objects = primitive_arrays(form, [state], [goal])
    n = 3
    on, on_g = prims["on"][0], prims["on_g"][0]
    for x in range(n):
        s, g = state.support[x], goal.support[x]
        assert on[x, s] if s != TABLE else (on[x, n] if not form.hand else not on[x].any())
        assert on_g[x, g] if g != TABLE else (on_g[x, n] if not form.hand else not on_g[x].any())
    assert list(prims["clear"][0][:n]) == [state.is_clear(b) for b in range(n)]
    if form.hand:
        assert bool(prims["handempty"][0]) and not prims["holding"][0].any()
        assert list(prims["ontable"][0]) == [s == TABLE for s in state.support]
    else:
        assert objects == n + 1 and prims["clear"][0][n] and list(prims["block"][0]) == [True] * n + [False]
    assert np.array_equal(on.sum(axis=1) <= 1, np.ones(objects, bool))
