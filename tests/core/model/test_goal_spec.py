"""Goals as atoms past six blocks: satisfiability, partial goals and the derived target (no enumeration)."""

import numpy as np
import pytest

from csql_sim.core.model.goal_spec import GoalError, GoalSpec, goal_target, holds, state_atoms
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.state_count import sample_state
from csql_sim.core.state.world import HAND, TABLE, State

A, B, C, D, E, F, G, H = range(8)


def goal(n, positive, negative=()):
    return GoalSpec(n, frozenset(positive), frozenset(negative))


def test_a_full_goal_of_eight_blocks_is_its_one_state():
    end = parse_config("HGFEDCBA")
    spec = GoalSpec.of_state(end)
    assert not spec.partial and spec.count == 1 and spec.states == (end,)
    assert spec.nearest(parse_config("A,B,C,D,E,F,G,H")) == end


def test_unplaced_blocks_keep_their_supports_where_the_goal_allows():
    start = parse_config("ABC,DEF,GH")
    spec = goal(8, {("on", (A, E)), ("on", (E, H))})
    target = spec.nearest(start)
    assert spec.partial and spec.count is None and spec.satisfied(target)
    assert target.support[B] == TABLE and target.support[C] == TABLE  # on A, which the goal moves: they move
    assert target.support[F] == TABLE  # stood on E, which the goal moves: to the table
    assert target.support[D] == TABLE and target.support[G] == TABLE and target.support[H] == G  # H stays put


def test_a_free_block_counts_as_well_placed_where_it_stands():
    start = parse_config("ABC,DEFG,H")
    spec = goal(8, {("on", (H, G)), ("on", (B, A))})  # A, C, D, E, F, G free; B placed where it stands
    target = spec.nearest(start)
    assert target.support[C] == B and target.support[E:G + 1] == (D, E, F)  # need not move: kept
    spec = goal(8, {("on", (A, H))})  # A must move, so must B and C above it: to the table, not back onto A
    target = spec.nearest(start)
    assert target.support[B] == TABLE and target.support[C] == TABLE and target.support[D:G + 1] == (TABLE, D, E, F)


def well_placed(state, target):
    """Blocks that keep their support in ``target`` and stand on blocks that do, down to the table."""
    out = set()
    for tower in state.towers():
        for i in tower:
            if target.support[i] != state.support[i] or (state.support[i] >= 0 and state.support[i] not in out):
                break
            out.add(i)
    return out


def test_a_required_clear_block_and_a_cycle_send_the_free_block_to_the_table():
    start = parse_config("AB,CD,EFGH")
    spec = goal(8, {("clear", (A,)), ("on", (C, D))})  # B stood on A; D stood on C, and C now goes on D
    target = spec.nearest(start)
    assert spec.satisfied(target) and target.support[B] == TABLE and target.support[D] == TABLE
    assert target.support[F:] == start.support[F:]


def test_negated_atoms_are_met_by_the_search():
    start = parse_config("ABC,DEF,GH")
    spec = goal(8, {("on", (B, A))}, {("on", (E, D)), ("on", (G, TABLE)), ("handempty", ())})
    target = spec.nearest(start)
    assert spec.satisfied(target) and target.held is not None and target.support[G] != TABLE


@pytest.mark.parametrize("positive, negative", [
    ({("on", (A, B)), ("on", (B, A))}, ()),
    ({("on", (A, B)), ("on", (C, B))}, ()),
    ({("on", (A, B)), ("clear", (B,))}, ()),
    ({("holding", (A,)), ("handempty", ())}, ()),
    ((), {("on", (i, TABLE)) for i in range(8)} | {("holding", (i,)) for i in range(8)}),
])
def test_unsatisfiable_goals_are_refused_in_one_line(positive, negative):
    with pytest.raises(GoalError, match="no state of the 8-block world satisfies the goal") as caught:
        goal(8, positive, negative)
    assert "\n" not in str(caught.value)


def test_the_target_satisfies_random_partial_goals_and_keeps_what_it_may():
    rng = np.random.default_rng(3)
    for _ in range(200):
        n = int(rng.integers(7, 11))
        start, end = sample_state(n, rng), sample_state(n, rng)
        atoms = sorted(state_atoms(end))
        keep = [atoms[i] for i in sorted(rng.choice(len(atoms), size=int(rng.integers(1, 4)), replace=False))]
        spec = goal(n, keep)
        target = goal_target(spec, start)
        assert spec.satisfied(target), (start, keep)
        placed = {args[0] for pred, args in keep if pred in ("on", "holding")}
        claimed = {args[1] for pred, args in keep if pred == "on"} | {args[0] for pred, args in keep if pred == "clear"}
        well = well_placed(start, target)
        for i in set(range(n)) - placed:  # a free block moves only to the table, and only when it must
            assert target.support[i] in (start.support[i], TABLE)
            assert target.support[i] != HAND
            below = start.support[i]
            must_move = below == HAND or (below >= 0 and (below not in well or below in claimed))
            assert (target.support[i] == below) == (not must_move) == (i in well), (start, keep, i)
        assert all(holds(a, target) for a in keep)


def test_a_relational_start_is_accepted_and_a_hand_goal_holds():
    start = State((TABLE,) * 7)
    spec = goal(7, {("holding", (C,))})
    assert spec.nearest(start).held == C
