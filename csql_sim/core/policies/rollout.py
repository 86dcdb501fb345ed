"""Greedy rollouts of any policy and all-pairs checks, on the world model's transitions.

* **greedy rollout**: :func:`rollout_indices` runs a policy from a start until the goal, a
  loop, an illegal action or the step cap; :func:`rollout` is the same for states.
* **all-pairs checking**: :func:`check_pairs` plans every ordered pair (goal by goal, so
  one goal's distances are held at a time) or a seeded sample, one :class:`PairPlan` each.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from dataclasses import dataclass

from csql_sim.core.model.pairs import sample_ranks, unrank
from csql_sim.core.model.search import BfsPolicy, bfs_choice, check_same_world, distance_list
from csql_sim.core.model.transition_table import TransitionTable, true_table
from csql_sim.core.model.world_model import WorldModel
from csql_sim.core.policies.policy import NoRuleError, Policy
from csql_sim.core.state.world import Action, BlocksWorld, State


@dataclass(frozen=True)
class PairPlan:
    """A policy's plan for one (start, goal) pair, in state and action indices.

    Attributes:
        n: number of blocks.
        start: start state index.
        goal: goal state index.
        actions: the action indices taken.
        reached: whether the plan reaches the goal.
        reason: why not ("" when reached).
        optimal_length: the BFS distance on the true world (-1 when not measured).
    """

    n: int
    start: int
    goal: int
    actions: tuple[int, ...]
    reached: bool
    reason: str = ""
    optimal_length: int = -1

    @property
    def steps(self) -> tuple[Action, ...]:
        """The actions taken, as actions."""
        actions = BlocksWorld.of(self.n).actions
        return tuple(actions[a] for a in self.actions)

    @property
    def length(self) -> int | None:
        """The plan's length, or None when it did not reach the goal."""
        return len(self.actions) if self.reached else None

    @property
    def optimal(self) -> bool:
        return self.reached and len(self.actions) == self.optimal_length


def rollout_indices(table: TransitionTable, choose: Callable[[int, int], int], start: int, goal: int,
                    cap: int | None = None, optimal_length: int = -1,
                    names: tuple[str, ...] | None = None) -> PairPlan:
    """Follow ``choose(state, goal)`` on ``table`` from ``start`` until the goal, a loop or the cap.

    Args:
        table: the transitions the plan runs on.
        choose: the action index to take; -1 or :class:`~csql_sim.core.policies.policy.NoRuleError`
            when the policy has none.
        start: start state index.
        goal: goal state index.
        cap: the step cap; defaults to the number of states (a longer path must revisit a state).
        optimal_length: recorded in the result.
        names: the blocks' names in the reason (a problem's objects; default the letters).
    """
    world, rows = BlocksWorld.of(table.n), table.rows

    def shown(s: int) -> str:
        return world.states[s].named(names).named_notation()

    cap = table.state_count if cap is None else cap
    state, taken, seen = start, [], {start}

    def stop(why: str) -> PairPlan:
        return PairPlan(table.n, start, goal, tuple(taken), False, why, optimal_length)

    while state != goal:
        if len(taken) >= cap:
            return stop(f"step cap {cap} reached")
        try:
            a = choose(state, goal)
        except NoRuleError as exc:
            return stop(str(exc))
        if a < 0:
            return stop(f"no Q-classifier for {shown(state)}")
        taken.append(a)
        nxt = rows[state][a]
        if nxt < 0:
            return stop(f"illegal action {world.actions[a].name(names)} in {shown(state)}")
        if nxt in seen:
            return stop(f"loop at {shown(nxt)}")
        seen.add(nxt)
        state = nxt
    return PairPlan(table.n, start, goal, tuple(taken), True, "", optimal_length)


def policy_choice(policy: Policy | None, n: int) -> Callable[[int, int], int]:
    """Any policy as a choice function over indices (None: BFS on the true world)."""
    if policy is None:
        return bfs_choice(true_table(n))
    if isinstance(policy, BfsPolicy):
        return policy._choice(n)
    if hasattr(policy, "action_index"):  # a greedy table answers in indices directly
        return policy.action_index
    world = BlocksWorld.of(n)

    def choose(s: int, g: int) -> int:
        return world.action_index(policy.act(world.states[s], world.states[g]))

    return choose


@dataclass(frozen=True)
class Rollout:
    """A symbolic execution of a policy.

    Attributes:
        actions: the actions taken.
        reached: whether the goal was reached.
        reason: why not, when it was not ("" on success).
    """

    actions: tuple[Action, ...]
    reached: bool
    reason: str = ""


def rollout(policy: Policy, start: State, goal: State, max_steps: int | None = None,
            world_model: WorldModel | None = None) -> Rollout:
    """Run ``policy`` on the world model from ``start`` until ``goal``, a loop or the cap.

    Args:
        policy: any policy.
        start: the start state.
        goal: the goal state.
        max_steps: the cap; defaults to the number of states.
        world_model: predicts each next state (default: the built-in R-classifiers).
    """
    check_same_world(start, goal)
    table = (world_model or WorldModel.for_blocks(start.n)).table
    plan = rollout_indices(table, policy_choice(policy, start.n), *_indices(start, goal), cap=max_steps,
                           names=start.names)
    return Rollout(plan.steps, plan.reached, plan.reason)


def _indices(start: State, goal: State) -> tuple[int, int]:
    world = BlocksWorld.of(start.n)
    return world.state_index(start), world.state_index(goal)


# ---------------------------------------------------------------- all-pairs checks


def check_pairs(policy: Policy | None, n: int, pairs: str | int = "all", seed: int = 0,
                world_model: WorldModel | None = None, progress: bool = False) -> Iterator[PairPlan]:
    """Plan every ordered pair of distinct states (goal by goal) or a seeded sample of ``pairs``.

    Args:
        policy: the policy to check; None checks BFS itself.
        n: number of blocks.
        pairs: ``"all"`` or the sample size K (drawn without listing the pairs, in rank order).
        seed: the sample's seed.
        world_model: the transitions the plans run on (default: the built-in R-classifiers).
        progress: a tqdm bar on stderr when it takes more than a second.
    """
    from tqdm import tqdm

    table = (world_model or WorldModel.for_blocks(n)).table
    choose = policy_choice(policy, n)
    count = table.state_count
    order = _all_pairs(count) if pairs == "all" else (unrank(r, count) for r in sample_ranks(count, pairs, seed))
    total = count * (count - 1) if pairs == "all" else int(pairs)
    with tqdm(total=total, desc="pairs", unit="pair", disable=not progress, leave=False, mininterval=0.5,
              delay=1.0) as bar:
        for start, goal in order:
            optimal = distance_list(goal, true_table(n))[start]
            yield rollout_indices(table, choose, start, goal, optimal_length=optimal)
            bar.update()


def _all_pairs(count: int) -> Iterator[tuple[int, int]]:
    for goal in range(count):
        for start in range(count):
            if start != goal:
                yield start, goal


def check_all_pairs(policy: Policy | None, n: int, world_model: WorldModel | None = None,
                    progress: bool = False) -> list[PairPlan]:
    """:func:`check_pairs` over every ordered pair, as a list (462 for n = 3)."""
    return list(check_pairs(policy, n, "all", world_model=world_model, progress=progress))
