"""The deadlock cover: enough and minimal table visitors, the same from scratch and compiled."""

import numpy as np

from csql_sim.core.measure.optimum import fewest_table_visits
from csql_sim.core.model.task_draws import tall_towers
from csql_sim.core.state.atom_names import ATOMS
from csql_sim.core.state.deadlock_cover import acyclic, deadlock_cover, events
from csql_sim.core.state.goal_relations import deadlocked, precedences
from csql_sim.core.state.move_relations import MoveRelations, target_goal
from csql_sim.core.state.moves import pick_action, put_action
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.relation_tracker import RelationTracker
from csql_sim.core.state.state_count import sample_pairs


def test_the_top_block_of_a_two_block_deadlock_visits_the_table():
    # A on B on the table; the goal puts A on B on C: B must move first, so A must visit the table
    state, goal = parse_config("BA,C"), parse_config("CBA")
    assert deadlocked(state, goal) == {0, 1}
    assert deadlock_cover(state, goal) == {0}


def test_the_cover_is_enough_minimal_and_no_smaller_than_the_fewest_visitors():
    rng = np.random.default_rng(5)
    pairs = [(s, g) for s, g in sample_pairs(8, 80, rng) if s.held is None and g.held is None]
    pairs += [(tall_towers(14, rng), tall_towers(14, rng)) for _ in range(30)]
    for state, goal in pairs:
        cover = deadlock_cover(state, goal)
        assert cover <= deadlocked(state, goal)
        assert acyclic(events(state, goal, cover))
        for b in cover:  # no visitor can be spared
            assert not acyclic(events(state, goal, cover - {b}))
        assert len(cover) >= fewest_table_visits(precedences(state, goal), state.n)


def test_the_compiled_cover_equals_the_reference_on_every_step():
    rng = np.random.default_rng(8)
    at = ATOMS.index("cover(?x)")
    for _ in range(12):
        state, goal = tall_towers(20, rng), tall_towers(20, rng)
        tracker = RelationTracker(state, goal)
        for _ in range(40):
            rel = MoveRelations(tracker.state(), target_goal(tracker.state(), goal))
            got = dict(tracker.candidates())
            for move, bits in got.items():
                assert bits[at] == rel.bits(move)[at]
            move = next(iter(got))
            action = tracker_action(tracker, move)
            tracker.apply(action)
            if tracker.state() == goal:
                break


def tracker_action(tracker, move):
    state = tracker.state()
    return put_action(move) if state.held is not None else pick_action(state, move.block)


def test_the_compiled_cover_equals_the_reference_on_larger_towers():
    # the compiled search runs from both ends of the dropped block's event; the reference checks the whole graph
    rng = np.random.default_rng(13)
    for n in (30, 45, 60, 60, 80):
        state, goal = tall_towers(n, rng), tall_towers(n, rng)
        assert RelationTracker(state, goal).cover == deadlock_cover(state, goal)
