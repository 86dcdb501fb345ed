"""Symbolic search: BFS distances, the optimal planner, greedy rollouts and all-pairs checks.

The one place for each of these:

* **distances**: :func:`distances_to` is a breadth-first search backwards from a goal on a
  :class:`~csql_sim.core.transition_table.TransitionTable`; on the true world
  (:func:`~csql_sim.core.transition_table.true_table`) it is the yardstick every learned
  plan is measured against, independent of any agent's knowledge.
* **the optimal planner**: :func:`distance`, :func:`optimal_actions`, :func:`bfs_plan` and
  :class:`BfsPolicy` (on the true world, or on what a world model's R-classifiers say).
* **greedy rollout**: :func:`rollout_indices` runs a policy from a start until the goal, a
  loop, an illegal action or the step cap; :func:`rollout` is the same for states.
* **all-pairs checking**: :func:`check_pairs` plans every ordered pair (goal by goal, so
  one goal's distances are held at a time) or a seeded sample, one :class:`PairPlan` each.
* **greedy argmax**: :func:`greedy_argmax`, the highest value per key, the first on ties.
"""

from __future__ import annotations

import functools
from collections import deque
from collections.abc import Callable, Iterator
from dataclasses import dataclass

import numpy as np

from csql_sim.core.pairs import sample_ranks, unrank
from csql_sim.core.policy import NoRuleError, Policy
from csql_sim.core.transition_table import TransitionTable, true_table
from csql_sim.core.world import Action, BlocksWorld, State, WorldError
from csql_sim.core.world_model import WorldModel


class NoPlanError(WorldError):
    """No plan exists (cannot happen in the blocks world, but named for callers)."""


# ---------------------------------------------------------------- distances


def reverse_bfs(preds: tuple[tuple[int, ...], ...], goal: int) -> np.ndarray:
    """Optimal plan length from every state to ``goal`` (-1: unreachable), by BFS on ``preds``."""
    dist = np.full(len(preds), -1, np.int32)
    dist[goal] = 0
    queue = deque([goal])
    while queue:
        s = queue.popleft()
        for p in preds[s]:
            if dist[p] < 0:
                dist[p] = dist[s] + 1
                queue.append(p)
    dist.setflags(write=False)
    return dist


@functools.lru_cache(maxsize=64)
def distances_to(goal: int, table: TransitionTable) -> np.ndarray:
    """Plan lengths from every state to state ``goal`` on ``table`` (read-only, memoized)."""
    return reverse_bfs(table.predecessors, goal)


def true_distances(n: int, goal: int) -> np.ndarray:
    """Optimal plan lengths to ``goal`` in the true n-block world (the yardstick)."""
    return distances_to(goal, true_table(n))


def distance(start: State, goal: State) -> int:
    """The optimal number of actions from ``start`` to ``goal``."""
    _check_same_world(start, goal)
    world = BlocksWorld.of(start.n)
    return int(true_distances(start.n, world.state_index(goal))[world.state_index(start)])


def _check_same_world(a: State, b: State) -> None:
    if a.n != b.n:
        raise WorldError(f"start has {a.n} blocks but goal has {b.n}")


# ---------------------------------------------------------------- the optimal planner


@functools.lru_cache(maxsize=64)
def _distance_list(goal: int, table: TransitionTable) -> list[int]:
    return distances_to(goal, table).tolist()


def _first_optimal(table: TransitionTable, dist: list[int], s: int) -> int:
    """The first action (stable order) of ``s`` that lies on a shortest path; -1 if none."""
    row, want = table.rows[s], dist[s] - 1
    for a in table.legal[s]:
        if dist[row[a]] == want >= 0:
            return a
    return -1


def optimal_actions(state: State, goal: State) -> tuple[Action, ...]:
    """Every legal action of ``state`` that lies on some optimal plan to ``goal``."""
    _check_same_world(state, goal)
    world, table = BlocksWorld.of(state.n), true_table(state.n)
    dist = true_distances(state.n, world.state_index(goal))
    s = world.state_index(state)
    if dist[s] == 0:
        return ()
    return tuple(world.actions[a] for a in table.legal[s] if dist[table.next_state[s, a]] == dist[s] - 1)


def bfs_plan(start: State, goal: State) -> tuple[Action, ...]:
    """An optimal plan from ``start`` to ``goal``; ties broken by the stable action order."""
    _check_same_world(start, goal)
    result = rollout_indices(true_table(start.n), _bfs_choice(true_table(start.n)), *_indices(start, goal))
    if not result.reached:
        raise NoPlanError(f"no plan from {start.notation()} to {goal.notation()}")
    return result.steps


def _bfs_choice(table: TransitionTable) -> Callable[[int, int], int]:
    """BFS as a choice function over indices (raises NoPlanError where the goal is unreachable)."""

    def choose(s: int, g: int) -> int:
        a = _first_optimal(table, _distance_list(g, table), s)
        if a < 0:
            states = BlocksWorld.of(table.n).states
            raise NoPlanError(f"the world model gives no plan from {states[s].notation()} to {states[g].notation()}")
        return a

    return choose


class BfsPolicy:
    """The policy interface backed by breadth-first search: an optimal next action.

    Args:
        world_model: plan on this world model's transition table; None (the default)
            plans on the true world.

    Ties are broken by the stable action order.
    """

    name = "bfs"

    def __init__(self, world_model: WorldModel | None = None) -> None:
        self.world_model = world_model
        self.blocks: int | None = None if world_model is None else world_model.n

    def act(self, state: State, goal: State) -> Action | None:
        """The first action of an optimal plan from ``state``, or None at the goal.

        Raises:
            NoPlanError: when the world model connects ``state`` to no path to ``goal``.
        """
        _check_same_world(state, goal)
        world = BlocksWorld.of(state.n)
        s, g = world.state_index(state), world.state_index(goal)
        if s == g:
            return None
        a = self._choice(state.n)(s, g)
        return world.actions[a]

    def action_index(self, state: int, goal: int) -> int:
        """:meth:`act` in state and action indices (the policy must know its n: a world model)."""
        assert self.blocks is not None, "BfsPolicy on the true world: use act(), or policy_choice(policy, n)"
        return self._choice(self.blocks)(state, goal)

    def _choice(self, n: int) -> Callable[[int, int], int]:
        table = true_table(n) if self.world_model is None else self.world_model.table
        return _bfs_choice(table)


# ---------------------------------------------------------------- greedy rollout


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
                    cap: int | None = None, optimal_length: int = -1) -> PairPlan:
    """Follow ``choose(state, goal)`` on ``table`` from ``start`` until the goal, a loop or the cap.

    Args:
        table: the transitions the plan runs on.
        choose: the action index to take; -1 or :class:`~csql_sim.core.policy.NoRuleError`
            when the policy has none.
        start: start state index.
        goal: goal state index.
        cap: the step cap; defaults to the number of states (a longer path must revisit a state).
        optimal_length: recorded in the result.
    """
    world, rows = BlocksWorld.of(table.n), table.rows
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
            return stop(f"no Q-classifier for {world.states[state].notation()}")
        taken.append(a)
        nxt = rows[state][a]
        if nxt < 0:
            return stop(f"illegal action {world.actions[a].name()} in {world.states[state].notation()}")
        if nxt in seen:
            return stop(f"loop at {world.states[nxt].notation()}")
        seen.add(nxt)
        state = nxt
    return PairPlan(table.n, start, goal, tuple(taken), True, "", optimal_length)


def policy_choice(policy: Policy | None, n: int) -> Callable[[int, int], int]:
    """Any policy as a choice function over indices (None: BFS on the true world)."""
    if policy is None:
        return _bfs_choice(true_table(n))
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
    _check_same_world(start, goal)
    table = (world_model or WorldModel.for_blocks(start.n)).table
    plan = rollout_indices(table, policy_choice(policy, start.n), *_indices(start, goal), cap=max_steps)
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
            optimal = _distance_list(goal, true_table(n))[start]
            yield rollout_indices(table, choose, start, goal, optimal_length=optimal)
            bar.update()


def _all_pairs(count: int) -> Iterator[tuple[int, int]]:
    for goal in range(count):
        for start in range(count):
            if start != goal:
                yield start, goal


@functools.lru_cache(maxsize=2)
def distance_matrix(n: int) -> np.ndarray:
    """``D[g, s]``: the optimal plan length from state ``s`` to goal ``g`` (all goals at once)."""
    table = true_table(n)
    return np.array([distances_to(g, table) for g in range(table.state_count)], dtype=np.int16)


def count_optimal_greedy(best: np.ndarray, n: int) -> int:
    """The (state, goal) pairs where a greedy table's action lowers the distance by one, vectorized.

    ``best[state * S + goal]`` is the table. A greedy policy plans a pair optimally when
    its action lowers the distance to the goal by one in every state on the way, so it
    plans every ordered pair optimally exactly when this count is ``S * (S - 1)`` (the
    scaling study's stopping test; for a partial count, :func:`check_pairs` rolls out).
    """
    table = true_table(n)
    count = table.state_count
    dist = distance_matrix(n)
    act = best.reshape(count, count)  # [state, goal]
    states, goals = np.arange(count)[:, None], np.arange(count)[None, :]
    nxt = np.where(act >= 0, table.next_state[states, np.maximum(act, 0)], -1)
    ok = (nxt >= 0) & (dist[goals, np.maximum(nxt, 0)] == dist[goals, states] - 1)
    return int(ok.sum())  # the diagonal never counts: its distance less one is -1


def check_all_pairs(policy: Policy | None, n: int, world_model: WorldModel | None = None,
                    progress: bool = False) -> list[PairPlan]:
    """:func:`check_pairs` over every ordered pair, as a list (462 for n = 3)."""
    return list(check_pairs(policy, n, "all", world_model=world_model, progress=progress))


# ---------------------------------------------------------------- greedy argmax


def greedy_argmax(keys: np.ndarray, values: np.ndarray, choices: np.ndarray, size: int) -> np.ndarray:
    """Per key in ``0..size-1``, the choice of the highest value (the first in order on ties); -1 where none.

    The vectorized form of "the action of the strongest matching classifier": ``keys``
    index (state, goal) pairs, ``values`` are the Q-values (or strengths), ``choices`` the
    action indices, all of one length and in classifier-list order.
    """
    order = np.lexsort((np.arange(len(keys)), -values, keys))
    first = np.ones(len(order), bool)
    first[1:] = keys[order][1:] != keys[order][:-1]
    best = np.full(size, -1, np.int8)
    best[keys[order][first]] = choices[order][first]
    return best
