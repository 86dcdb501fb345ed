"""The policy interface shared by the symbolic and the physical executor, and rollouts.

Two policies implement it: :class:`csql_sim.core.planner.BfsPolicy` (optimal, from the world
model) and :class:`QPolicy` (greedy over learned Q-classifiers).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Protocol

from csql_sim.core.classifier_list import ClassifierList
from csql_sim.core.message import format_state_message, parse_action_message
from csql_sim.core.planner import distance
from csql_sim.core.rulebase import RuleBase
from csql_sim.core.world import Action, BlocksWorld, State
from csql_sim.core.world_model import WorldModel
from csql_sim.infra.errors import CsqlError

VALUES = ("q", "strength")


class Policy(Protocol):
    """Anything that proposes the next action towards a goal; None at the goal.

    Attributes:
        name: ``"bfs"`` or ``"rules"``.
        blocks: the number of blocks it is for, or None when any.

    """

    name: str
    blocks: int | None

    def act(self, state: State, goal: State) -> Action | None:
        """The action to take in ``state`` to reach ``goal``."""
        ...


class NoRuleError(CsqlError):
    """A rule base has no Q-classifier for a state message."""


class QPolicy:
    """Greedy policy over Q-classifiers: the action of the highest value (ties: list order).

    Args:
        classifiers: a classifier list holding Q-classifiers (R-classifiers are ignored).
        n: number of blocks the messages describe.
        value: the field greedy selection follows: ``"q"`` (Q-learning) or
            ``"strength"`` (the bucket brigade's learned value).

    """

    name = "rules"

    def __init__(self, classifiers: ClassifierList, n: int, value: str = "q") -> None:
        if value not in VALUES:
            raise CsqlError(f"value must be one of {', '.join(VALUES)}, got {value!r}")
        self.classifiers = classifiers
        self.n = self.blocks = n
        self.value = value
        self.world = BlocksWorld.of(n)

    @classmethod
    def from_rulebase(cls, rulebase: RuleBase) -> QPolicy:
        """The greedy policy of a rule base (its ``meta["value"]`` names the field, default q)."""
        return cls(ClassifierList(rulebase.classifiers), rulebase.blocks, rulebase.meta.get("value", "q"))

    def act(self, state: State, goal: State) -> Action | None:
        """The greedy action; raises NoRuleError naming the state message if none matches."""
        if state == goal:
            return None
        message = format_state_message(state, self.world.state_index(goal))
        rules = self.classifiers.q_for(message).values()
        if not rules:
            raise NoRuleError(f"no Q-classifier matches state {message} ({state.notation()})")
        field = self.value
        best = max(rules, key=lambda c: getattr(c, field))  # max keeps the first of equal values
        return parse_action_message(best.action, self.n)


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
        max_steps: the cap; defaults to the number of states (a longer greedy path must
            revisit a state).
        world_model: predicts each next state (default: the built-in R-classifiers).

    """
    model = world_model or WorldModel.for_blocks(start.n)
    cap = max_steps if max_steps is not None else len(BlocksWorld.of(start.n).states)
    state, taken, seen = start, [], {start}
    while state != goal:
        if len(taken) >= cap:
            return Rollout(tuple(taken), False, f"step cap {cap} reached")
        try:
            action = policy.act(state, goal)
        except NoRuleError as exc:
            return Rollout(tuple(taken), False, str(exc))
        taken.append(action)
        if not model.is_legal(state, action):
            return Rollout(tuple(taken), False, f"illegal action {action.name()} in {state.notation()}")
        state = model.predict_state(state, action)
        if state in seen and state != goal:
            return Rollout(tuple(taken), False, f"loop at {state.notation()}")
        seen.add(state)
    return Rollout(tuple(taken), True)


@dataclass(frozen=True)
class PairResult:
    """One (start, goal) pair of an all-pairs check."""

    start: State
    goal: State
    rollout: Rollout
    optimal_length: int

    @property
    def length(self) -> int | None:
        return len(self.rollout.actions) if self.rollout.reached else None

    @property
    def optimal(self) -> bool:
        return self.length == self.optimal_length


def check_all_pairs(policy: Policy, n: int, world_model: WorldModel | None = None,
                    progress: bool = False) -> list[PairResult]:
    """Roll ``policy`` out on one world model for every ordered pair of distinct states (462 for n=3).

    Args:
        policy: the policy to check.
        n: number of blocks.
        world_model: the model the rollouts run on (default: the built-in R-classifiers).
        progress: show a tqdm bar on stderr when it takes more than a second (n=5 has
            749,090 pairs).
    """
    from tqdm import tqdm

    model = world_model or WorldModel.for_blocks(n)
    states = BlocksWorld.of(n).states
    results = []
    with tqdm(total=len(states) * (len(states) - 1), desc="pairs", unit="pair", disable=not progress,
              leave=False, mininterval=0.5, delay=1.0) as bar:
        for g in states:
            for s in states:
                if s != g:
                    results.append(PairResult(s, g, rollout(policy, s, g, world_model=model), distance(s, g)))
            bar.update(len(states) - 1)
    return results


def load_policy(path: str | os.PathLike | None, n: int | None = None, progress: bool = False) -> Policy:
    """The greedy policy of a rule base from ``csql-sim train``, or BFS when ``path`` is None.

    Args:
        path: a rule-base file, or None for the BFS planner.
        n: the number of blocks the caller expects (checked against the rule file's
            header before its classifiers are parsed).
        progress: show a bar while a large rule file is parsed.

    Raises:
        CsqlError: if the file is missing, corrupt, foreign, or for another number of blocks.
    """
    from csql_sim.core.greedy_table import GreedyTable
    from csql_sim.core.planner import BfsPolicy

    if path is None:
        return BfsPolicy()
    table = GreedyTable.load(path, blocks=n, progress=progress)  # QPolicy's answers as a table, YAML or npz
    if n is not None and table.n != n:
        raise CsqlError(f"rule base {os.fspath(path)!r} is for {table.n} blocks, not {n}")
    return table
