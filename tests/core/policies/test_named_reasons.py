"""A rollout's reasons show a named problem's blocks by their names, whichever rollout made the plan."""

import pytest

from csql_sim.core.policies.relational_rollout import rollout_relational
from csql_sim.core.policies.rollout import rollout
from csql_sim.core.state.state import TABLE, State
from csql_sim.core.state.world import Action, ActionKind

NAMES = ("amber", "pearl", "onyx", "jade", "ruby", "opal", "coral", "ivory")


class PickAndPut:
    """Picks the first block from the table and puts it back: a loop after two actions."""

    name = "pick-and-put"
    blocks = None

    def act(self, state: State, goal: State) -> Action:
        if state.held is None:
            return Action(ActionKind.PICKUP, 0)
        return Action(ActionKind.PUTDOWN, state.held)


@pytest.mark.parametrize("n", [4, 8])
def test_a_loop_is_reported_in_the_problems_names(n):
    names = NAMES[:n]
    start = State((TABLE,) * n, names)
    goal = State((TABLE, 0) + (TABLE,) * (n - 2))
    run = rollout(PickAndPut(), start, goal) if n <= 6 else rollout_relational(PickAndPut(), start, goal)
    assert not run.reached
    assert run.reason == "loop at " + ", ".join(names)  # one-block towers, in the names; no cube letters
    unnamed = rollout(PickAndPut(), start.named(None), goal) if n <= 6 else \
        rollout_relational(PickAndPut(), start.named(None), goal)
    assert unnamed.reason == "loop at " + ",".join("ABCDEFGH"[:n])
