"""The incremental move relations agree with the from-scratch ones on every move of seeded random walks."""

import numpy as np
import pytest

from csql_sim.core.state.move_relations import MoveRelations, target_goal
from csql_sim.core.state.relation_tracker import RelationTracker
from csql_sim.core.state.state_count import sample_state
from csql_sim.core.state.world import HAND, TABLE, Action, ActionKind, State, WorldError, legal_actions, successor


def _classes(relations: MoveRelations) -> list:
    """The first move of each (block, kind, relations) class, in move order."""
    first: dict = {}
    for move in relations.moves:
        first.setdefault((move.block, move.kind, relations.bits(move)), move)
    return sorted(first.values(), key=relations.moves.index)


def _agree(tracker: RelationTracker, state: State, target: State) -> None:
    want = MoveRelations(state, target)
    assert tracker.support == state.support
    assert tracker.moves() == want.moves
    assert tracker.stuck == want.stuck
    assert tracker.stuck_after == want.stuck_after
    assert [tracker.bits(m) for m in want.moves] == [want.bits(m) for m in want.moves]
    assert [m for m, _ in tracker.candidates()] == _classes(want)
    assert tracker.misplaced() == want.misplaced()


@pytest.mark.parametrize("n", [3, 5, 8, 12])
def test_incremental_relations_equal_the_from_scratch_ones_on_every_step_of_random_walks(n):
    rng = np.random.default_rng(n)
    steps = 0
    for _ in range(6):
        goal = sample_state(n, rng)
        state = sample_state(n, rng)
        target = target_goal(state, goal) if goal.held is None else target_goal(State((TABLE,) * n), goal)
        tracker = RelationTracker(state, target)
        for _ in range(40):
            _agree(tracker, state, target)
            _agree(RelationTracker(state, target), state, target)
            options = legal_actions(state)
            action = options[int(rng.integers(len(options)))]
            tracker.apply(action)
            state = successor(state, action)
            steps += 1
    assert steps == 6 * 40


def test_deferred_least_stuck_is_unknown_until_resolved_and_then_exact():
    # A B C D from the table up, towards A B D C: C and D block each other (a deadlock).
    state, target = State((TABLE, 0, 1, 2)), State((TABLE, 0, 3, 1))
    tracker = RelationTracker(state, target)
    assert tracker.stuck == frozenset({2, 3})
    assert [bits[5] for _, bits in tracker.candidates(resolve=False)][0] == -1
    assert tracker.stuck_after == MoveRelations(state, target).stuck_after
    assert [bits[5] for _, bits in tracker.candidates(resolve=False)][0] in (0, 1)


def test_an_illegal_action_is_refused_and_any_n_is_accepted():
    n = 600
    tracker = RelationTracker(State((TABLE,) * n), State((TABLE, *range(n - 1))))
    assert tracker.misplaced() == n - 1
    with pytest.raises(WorldError):
        tracker.apply(Action(ActionKind.STACK, 1, 0))
    tracker.apply(Action(ActionKind.PICKUP, 1))
    assert tracker.support[1] == HAND
    with pytest.raises(WorldError):
        tracker.apply(Action(ActionKind.PICKUP, 2))
    tracker.apply(Action(ActionKind.STACK, 1, 0))
    assert tracker.misplaced() == n - 2
