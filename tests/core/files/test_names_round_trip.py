"""Block names round-trip through PDDL problems, IPC plan files and JSON; plans ignore the listing order."""

import json
import random

import pytest

from csql_sim.core.files.ipc_plan import parse_plan, plan_index, read_plan, write_ipc_plan
from csql_sim.core.files.pddl_export import blocks_problem_text
from csql_sim.core.files.pddl_import import parse_problem_text
from csql_sim.core.model.search import bfs_plan
from csql_sim.core.policies.gn1 import Gn1Policy
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.world import State, successor

NAMES = ("Red", "b10", "b2", "GREEN", "x-1")


def _named(text: str, names: tuple[str, ...]) -> State:
    return parse_config(text).named(names)


def test_names_round_trip_through_a_pddl_problem():
    start, goal = _named("AB,E,C+D", NAMES), _named("EDCBA", NAMES)
    text = blocks_problem_text(start, goal, name="colours")
    problem = parse_problem_text(text)
    # the importer orders blocks by name (numbers as numbers), so indices may move; names travel with them
    by_name = {problem.names[i]: i for i in range(problem.n)}
    assert sorted(problem.names) == sorted(NAMES)  # as written, upper case kept
    assert problem.objects == tuple(name.lower() for name in problem.names)
    for i, name in enumerate(NAMES):
        below = start.support[i]
        want = below if below < 0 else by_name[NAMES[below]]
        assert problem.start.support[by_name[name]] == want
    again = parse_problem_text(blocks_problem_text(problem.start, problem.goal.states[0]))
    assert again.names == problem.names and again.start == problem.start
    assert again.goal.states == problem.goal.states


def test_names_compare_without_case():
    state = _named("AB", ("Red", "blue"))
    assert state.index_of("RED") == 0 and state.index_of("Blue") == 1
    with pytest.raises(ValueError, match="given twice"):
        _named("AB", ("red", "RED"))
    with pytest.raises(ValueError, match="no block is called"):
        state.index_of("green")


def test_object_order_in_the_file_does_not_change_the_task_or_the_plan():
    objects = ["b1", "b2", "b10", "Top", "c3", "a7"]
    init = "(handempty) (ontable b10) (on b2 b10) (on b1 b2) (clear b1) (ontable Top) (clear Top) " \
           "(ontable c3) (on a7 c3) (clear a7)"
    goal = "(and (on b10 b1) (on Top b10) (on c3 b2))"
    seen = set()
    for seed in range(5):
        listed = objects[:]
        random.Random(seed).shuffle(listed)
        p = parse_problem_text(f"(define (problem p) (:domain blocks) (:objects {' '.join(listed)}) "
                               f"(:init {init}) (:goal {goal}))")
        assert p.names == ("a7", "b1", "b2", "b10", "c3", "Top")  # sorted by name, b2 before b10
        plan = bfs_plan(p.start, p.goal.nearest(p.start))
        seen.add((p.start, tuple(a.name(p.names) for a in plan)))
    assert len(seen) == 1


def test_names_round_trip_through_a_plan_file(tmp_path):
    start, goal = _named("ABCDE", NAMES), _named("A,B,C,D,E", NAMES)
    policy, state, actions = Gn1Policy(), start, []
    while (action := policy.act(state, goal)) is not None:
        actions.append(action)
        state = successor(state, action)
    assert state == goal and state.names == NAMES  # the transition keeps the names
    path = write_ipc_plan(actions, tmp_path / "p.plan", names=start.block_names)
    text = path.read_text()
    assert "(unstack x-1 GREEN)" in text  # written as the user wrote them
    steps = read_plan(path, plan_index(start.block_names), start.n)
    assert [a for s in steps for a in s.actions] == actions
    upper = [line.upper() for line in text.splitlines()]  # PDDL names ignore case
    assert [a for s in parse_plan(upper, plan_index(start.block_names), start.n) for a in s.actions] == actions


def test_names_round_trip_through_json():
    for state in (_named("AB,E,C+D", NAMES), parse_config("ZYX,ABCDEFGHIJKLMNOPQRSTU,V+W")):
        back = State.from_json(json.loads(json.dumps(state.to_json())))
        assert back == state and back.names == state.names and back.block_names == state.block_names
    with pytest.raises(ValueError, match="not a state object"):
        State.from_json({"names": None})
