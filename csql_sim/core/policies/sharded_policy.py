"""The greedy policy of a sharded rule base, read lazily: a pair touches only its goal's shard.

:class:`ShardedPolicy` answers what :class:`~csql_sim.core.policies.policy.QPolicy` would answer for
the same Q-classifiers (the candidate with the highest Q-value, the first on ties), reading
the shard of the goal asked for (memory-mapped, checked against the manifest's SHA-256
once) and nothing else; so checking K sampled pairs opens at most K shards. The
candidates of a state come from the manifest's R-classifiers (their world model).
"""

from __future__ import annotations

import math
import os

import numpy as np

from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.classifiers.r_classifier import r_classifiers
from csql_sim.core.files.rulebase import RuleBase
from csql_sim.core.files.rulebase_shards import MANIFEST, ShardedRuleBase, greedy_ranks
from csql_sim.core.files.rulebase_yaml import RuleBaseError
from csql_sim.core.model.world_model import WorldModel
from csql_sim.core.policies.contract import Policy
from csql_sim.core.policies.policy import NoRuleError
from csql_sim.core.state.message import format_action_message, format_state_message
from csql_sim.core.state.world import Action, BlocksWorld, State


class ShardedPolicy(Policy):
    """Greedy policy over a sharded rule base's Q-classifiers.

    Args:
        base: the opened rule base (:class:`~csql_sim.core.files.rulebase_shards.ShardedRuleBase`).

    Attributes:
        name: ``"rules"``.
        blocks: its number of blocks.

    """

    name = "rules"

    def __init__(self, base: ShardedRuleBase) -> None:
        self.base = base
        self.n = self.blocks = base.blocks
        self.world = BlocksWorld.of(self.n)
        if len(self.world.states) != base.count:
            raise RuleBaseError(f"{base.directory}: {base.count} states in the manifest, {len(self.world.states)} "
                                f"in the {self.n}-block world")
        built_in = [[r.condition, r.action] for r in r_classifiers(self.n)]
        if base.manifest["r_classifiers"] != built_in:  # sharded training uses the built-in ones only
            raise RuleBaseError(f"{base.directory}: the manifest's R-classifiers are not the {self.n}-block world's")
        unit = base.manifest["params"].get("age_unit", 10_000.0)  # read_manifest checked params is an object
        if type(unit) not in (int, float) or not 0 < unit < math.inf:
            raise RuleBaseError(f"{base.directory / MANIFEST}: field 'params': age_unit must be a positive number, "
                                f"got {str(unit)[:20]!r}")
        self.age_unit = float(unit)
        self.model = WorldModel.for_blocks(self.n)
        self.legal = self.model.table.legal

    @classmethod
    def open(cls, path: str | os.PathLike, n: int | None = None) -> ShardedPolicy:
        """The policy of the sharded rule base at ``path`` (for ``n`` blocks, if given)."""
        return cls(ShardedRuleBase.open(path, n))

    def action_index(self, state: int, goal: int) -> int:
        """The greedy action index in state ``state`` for ``goal``, or -1 without a Q-classifier."""
        arrays, first = self.base.node(state, goal)
        legal = self.legal[state]
        if first < 0 or first + len(legal) > len(arrays.q):
            return -1
        return int(legal[int(np.argmax(arrays.q[first:first + len(legal)]))])  # argmax: the first on ties

    def columns(self, goals: tuple[int, ...]) -> np.ndarray:
        """The greedy action index of every state for each of ``goals`` (rows), -1 where none; their shards only."""
        count = len(self.world.states)
        out = np.full((len(goals), count), -1, np.int16)
        widths = np.array([len(x) for x in self.legal])
        lo = np.zeros(count + 1, np.int64)
        lo[1:] = np.cumsum(widths)
        flat = np.array([a for x in self.legal for a in x], np.int16)
        for k, g in enumerate(goals):
            arrays, start = self.base.column(g)
            first = np.asarray(arrays.first[start:start + count])
            rank = greedy_ranks(first, arrays.q, widths, count)
            ok = rank >= 0
            out[k, ok] = flat[lo[:-1][ok] + rank[ok]]
        return out

    def act(self, state: State, goal: State) -> Action | None:
        """The greedy action; raises NoRuleError if no Q-classifier matches."""
        return _act(self, state, goal)


def path_rulebase(policy: ShardedPolicy, start: State, goal: State) -> RuleBase:
    """The R-classifiers and the Q-classifiers of the greedy path from ``start`` to ``goal`` (for ``show``).

    The path follows the greedy candidates through the manifest's world model, at most
    one step per state; each state's Q-classifiers for ``goal`` come from the goal's shard.
    """
    base, world, n = policy.base, policy.world, policy.n
    unit = policy.age_unit
    g = world.state_index(goal)
    arrays, column = base.column(g)
    out: list = list(r_classifiers(n))
    s, seen = world.state_index(start), set()
    while s != g and s not in seen:
        seen.add(s)
        first = int(arrays.first[column + s])
        if first < 0:
            break
        message = format_state_message(world.states[s], g)
        born = int(arrays.born[column + s])
        for k, a in enumerate(policy.legal[s]):
            error = float(arrays.error[first + k])
            out.append(QClassifier(message, format_action_message(world.actions[a], n), float(arrays.q[first + k]),
                                   1.0 - error, (arrays.clock - born) / unit, error, arrays.clock, born))
        s = int(policy.model.table.next_state[s, policy.action_index(s, g)])
    return RuleBase(blocks=n, classifiers=out, meta={"sharded": str(base.directory)})


class GoalColumns:
    """A greedy policy over some goals only: a sharded rule base's columns as an evaluation's workers get them.

    Args:
        n: number of blocks.
        goals: the goals (ascending state indices).
        best: ``best[k * S + state]``, the action index for ``goals[k]`` (-1: none).

    """

    name = "rules"

    def __init__(self, n: int, goals: tuple[int, ...], best: np.ndarray) -> None:
        self.n = self.blocks = n
        self.world = BlocksWorld.of(n)
        self.row = {g: k for k, g in enumerate(goals)}
        self.best = best

    def action_index(self, state: int, goal: int) -> int:
        """The greedy action index, or -1 (also for a goal not shipped)."""
        k = self.row.get(goal)
        return -1 if k is None else int(self.best[k * len(self.world.states) + state])

    def act(self, state: State, goal: State) -> Action | None:
        """The greedy action; raises NoRuleError if no Q-classifier matches."""
        return _act(self, state, goal)


def _act(policy: ShardedPolicy | GoalColumns, state: State, goal: State) -> Action | None:
    if state == goal:
        return None
    s, g = policy.world.state_index(state), policy.world.state_index(goal)
    a = policy.action_index(s, g)
    if a < 0:
        raise NoRuleError(f"no Q-classifier matches state {format_state_message(state, g)} ({state.notation()})")
    return policy.world.actions[a]
