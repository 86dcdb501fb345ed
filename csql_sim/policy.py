"""The policy interface shared by the symbolic and the physical executor, and rollouts.

Two policies implement it: :class:`csql_sim.planner.BfsPolicy` (optimal, from the world
model) and :class:`QPolicy` (greedy over learned Q-classifiers).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

from csql_sim.classifiers import ClassifierList, Q
from csql_sim.errors import CsqlError
from csql_sim.messages import format_state_message, parse_action_message
from csql_sim.planner import distance
from csql_sim.world import Action, BlocksWorld, State, WorldError, successor


class Policy(Protocol):
    """Anything that proposes the next action towards a goal; None at the goal."""

    name: str

    def act(self, state: State, goal: State) -> Action | None:
        """The action to take in ``state`` to reach ``goal``."""
        ...


class NoRuleError(CsqlError):
    """A rule base has no Q-classifier for a state message."""


class QPolicy:
    """Greedy policy over Q-classifiers: the action of the highest Q-value (ties: list order).

    Args:
        classifiers: a classifier list holding Q-classifiers (R-classifiers are ignored).
        n: number of blocks the messages describe.

    """

    name = "rules"

    def __init__(self, classifiers: ClassifierList, n: int) -> None:
        self.classifiers = classifiers
        self.n = n
        self.world = BlocksWorld.of(n)

    def act(self, state: State, goal: State) -> Action | None:
        """The greedy action; raises NoRuleError naming the state message if none matches."""
        if state == goal:
            return None
        message = format_state_message(state, self.world.state_index(goal))
        rules = [c for c in self.classifiers.q_for(message).values() if c.kind == Q]
        if not rules:
            raise NoRuleError(f"no Q-classifier matches state {message} ({state.notation()})")
        best = max(rules, key=lambda c: c.q)  # max keeps the first of equal values
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


def rollout(policy: Policy, start: State, goal: State, max_steps: int | None = None) -> Rollout:
    """Run ``policy`` on the world model from ``start`` until ``goal``, a loop or the cap.

    The cap defaults to the number of states (a longer greedy path must revisit a state).
    """
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
        try:
            state = successor(state, action)
        except WorldError:
            return Rollout(tuple(taken), False, f"illegal action {action.name()} in {state.notation()}")
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


def check_all_pairs(policy: Policy, n: int) -> list[PairResult]:
    """Roll ``policy`` out for every ordered pair of distinct states (462 for n=3)."""
    states = BlocksWorld.of(n).states
    return [
        PairResult(s, g, rollout(policy, s, g), distance(s, g)) for g in states for s in states if s != g
    ]
