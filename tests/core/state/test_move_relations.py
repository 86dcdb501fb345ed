"""The relations of a move: the atoms as documented."""

import numpy as np

from csql_sim.core.state.atom_names import ATOMS
from csql_sim.core.state.goal_relations import deadlocked, well_placed
from csql_sim.core.state.move_relations import MoveRelations, target_goal
from csql_sim.core.state.moves import Move, after
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.state_count import sample_pairs
from csql_sim.core.state.world import TABLE


def test_relations_follow_their_definitions():
    state, goal = parse_config("CAB,ED"), parse_config("ABC,DE")
    rel = MoveRelations(state, goal)
    assert len(ATOMS) == 9
    placed = well_placed(state, goal)
    stuck = deadlocked(state, goal)
    for m in rel.moves:
        bits = rel.bits(m)
        assert bits[0] == (not placed[m.block])
        assert bits[1] == (goal.support[m.block] == m.onto)
        assert bits[3] == (m.block in stuck)
        assert bits[6] == bool(stuck)
        assert bits[7] == 0  # the hand is empty: no move is the put of a held block
    held = MoveRelations(parse_config("CA,ED+B"), goal)
    assert held.moves and all(held.bits(m)[7] == 1 for m in held.moves)
    # goal: E on the table, D on E. With E clear on A (misplaced), D onto E is not for good
    goal = parse_config("ABC,ED")
    assert MoveRelations(parse_config("AE,D,CB"), goal).bits(Move(3, 4))[:3] == (1, 1, 0)
    # with E on the table (its goal place), D onto E is a constructive move
    assert MoveRelations(parse_config("E,D,CAB"), goal).bits(Move(3, 4))[:3] == (1, 1, 1)


def test_least_stuck_marks_the_table_moves_that_leave_the_fewest_deadlocked_blocks():
    rng = np.random.default_rng(3)
    for state, goal in sample_pairs(8, 40, rng):
        target = target_goal(state, goal)
        if state == target:
            continue
        rel = MoveRelations(state, target)
        table = [m for m in rel.moves if m.onto == TABLE]
        counts = {m: len(deadlocked(after(state, m), target)) for m in table}
        for m in rel.moves:
            assert rel.bits(m)[5] == (m in counts and counts[m] == min(counts.values()))


def test_target_goal_keeps_a_held_goal_block_where_it_can_stay():
    state = parse_config("AB,C")
    assert target_goal(state, parse_config("A,C+B")).notation() == "AB,C"  # B may stay on A
    assert target_goal(state, parse_config("AC+B")).notation() == "AC,B"  # C goes on A, so B to the table
    assert target_goal(state, parse_config("BA,C")) == parse_config("BA,C")
