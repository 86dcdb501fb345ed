"""The move generator: legal by the STRIPS operators."""

from csql_sim.core.state.moves import Move, after, moves, pick_action, put_action
from csql_sim.core.state.state_count import state_count, unrank_state
from csql_sim.core.state.world import TABLE, is_legal, successor


def test_moves_are_exactly_the_legal_pick_and_put_pairs_at_four_blocks():
    for rank in range(state_count(4)):
        state = unrank_state(rank, 4)
        got = set(moves(state))
        want = set()
        for x in range(4):
            for onto in (TABLE, 0, 1, 2, 3):
                held = state if state.held == x else None
                if held is None and state.held is None and is_legal(state, pick_action(state, x)):
                    held = successor(state, pick_action(state, x))
                if held is None or onto == x or onto == state.support[x]:
                    continue
                if is_legal(held, put_action(Move(x, onto))):
                    want.add(Move(x, onto))
        assert got == want, state.notation()
        for m in got:
            assert after(state, m).support[m.block] == m.onto
