"""Rule discovery: the agent plays with the blocks and induces its own R-classifiers.

From the perceived state the agent attempts an action drawn uniformly from *all* action
messages of the world (not only the legal ones), executes it, perceives again and records
a :class:`~csql_sim.discovery.induction.Experience`. After every transition the rules of the
attempted action are induced again (:mod:`csql_sim.discovery.induction`). Exploration stops
when the rule set has not changed for ``Exploration.patience`` transitions (1000, or twice
the number of distinct (state, action) pairs tried so far if that is more: 1000 for n = 3,
about 8000 for n = 4), or after ``max_transitions``. Actions are chosen by
:class:`Curiosity` (untried actions first, then half balanced, half towards the least
visited states).

The world is anything with the :class:`~csql_sim.discovery.world.ExplorableWorld` protocol:
:class:`~csql_sim.discovery.world.SymbolicWorld` (an illegal action fails and changes nothing;
``perturb`` knocks a tower top onto the table now and then), or the simulated arm
(:mod:`csql_sim.sim.exploration`). State messages use goal code 0 throughout (exploration
has no goal), so the goal position never varies and induces nothing.
"""

from __future__ import annotations

import time
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from csql_sim.core.message import action_messages, format_action_message, format_state_message
from csql_sim.core.r_classifier import PreconditionRule, RClassifier, r_classifiers
from csql_sim.core.world import all_actions, all_states, is_legal, successor
from csql_sim.discovery.induction import (
    RELIABILITY,
    Evidence,
    Experience,
    InducedRules,
    Reliability,
    induce_action,
    rule_list,
)
from csql_sim.discovery.world import ExplorableWorld

EXPLORATION_GOAL = 0  # goal code of every state message during exploration


@dataclass(frozen=True)
class Exploration:
    """When exploration stops and what the rules must satisfy."""

    max_transitions: int = 50000  # --transitions K
    stable_for: int = 1000  # stop once the rule set has not changed for this many transitions,
    stable_per_pair: float = 2.0  # or for this many per distinct (state, action) pair tried, if more

    def patience(self, pairs_tried: int) -> int:
        """Transitions without a change after which exploration stops."""
        return max(self.stable_for, int(self.stable_per_pair * pairs_tried))
    reliability: Reliability = RELIABILITY


@dataclass
class DiscoveryResult:
    """The outcome of one discovery run."""

    n: int
    transitions: int = 0
    failed: int = 0
    restarts: int = 0
    last_change: int = 0  # transitions seen when the rule set last changed
    failed_to_final: int = 0  # failed attempts among those transitions
    stopped: str = ""  # "stable" or "cap"
    sim_seconds: float = 0.0
    wall_seconds: float = 0.0
    rules: list[RClassifier] = field(default_factory=list)
    events: list[str] = field(default_factory=list)
    log: list[Experience] = field(default_factory=list)

    def comparison(self) -> list[dict]:
        """Each given R-classifier: the induced one in its place, and whether they are equal."""
        return compare_rules(self.rules, self.n)

    @property
    def equal_to_given(self) -> bool:
        """True when the induced rules are the given ones, string for string."""
        given = r_classifiers(self.n)
        return [(c.condition, c.action) for c in self.rules] == [(c.condition, c.action) for c in given]


def rule_key(rule: RClassifier) -> str:
    """What identifies a rule's place: its action message, or its add-delete condition."""
    return rule.action if isinstance(rule, PreconditionRule) else rule.condition


def compare_rules(rules: list[RClassifier], n: int) -> list[dict]:
    """Per given rule (paper asset for n=3, generated otherwise): the induced rule and equality."""
    induced = {rule_key(r): r for r in rules}
    rows = []
    for g in r_classifiers(n):
        got = induced.get(rule_key(g))
        kind = "precondition" if isinstance(g, PreconditionRule) else "add-delete"
        rows.append({"kind": kind, "given": f"{g.condition} -> {g.action}",
                     "induced": None if got is None else f"{got.condition} -> {got.action}",
                     "equal": got is not None and (got.condition, got.action) == (g.condition, g.action)})
    return rows


Progress = Callable[[DiscoveryResult], None]


def explore(world: ExplorableWorld, rng: np.random.Generator, settings: Exploration = Exploration(),
            progress: Progress | None = None, keep_log: bool = True) -> DiscoveryResult:
    """Explore ``world`` with uniformly random actions and induce its R-classifiers.

    Args:
        world: the world (symbolic or physical).
        rng: the generator that draws the actions.
        settings: stopping rule and reliability thresholds.
        progress: called after every transition (e.g. a progress line).
        keep_log: keep every transition in the result (for --log).
    """
    n = world.n
    actions = all_actions(n)
    messages = action_messages(n)
    result = DiscoveryResult(n)
    evidence = Evidence(n)
    induced: dict[str, InducedRules] = {}
    curiosity = Curiosity(len(actions), rng)
    t0 = time.perf_counter()
    state = world.perceive()
    while result.transitions < settings.max_transitions:
        if state is None:
            result.restarts += 1
            world.restart()
            state = world.perceive()
            continue
        before = format_state_message(state, EXPLORATION_GOAL)
        k = curiosity.choose(before)
        attempt = world.attempt(actions[k])
        after = world.perceive()
        result.sim_seconds += attempt.sim_seconds
        result.events.extend(attempt.events)
        if after is None:  # the scene cannot be described: no transition to learn from
            result.events.append(f"after {actions[k].name()}: nothing perceived, new episode")
            state = None
            continue
        record = Experience(before, messages[k], format_state_message(after, EXPLORATION_GOAL), attempt.ok,
                            attempt.reason, attempt.refused)
        curiosity.remember(before, k, record.after)
        evidence.add(record)
        result.transitions += 1
        result.failed += not attempt.ok
        if keep_log:
            result.log.append(record)
        new = induce_action(evidence, messages[k], settings.reliability)
        if messages[k] not in induced or induced[messages[k]].strings() != new.strings():
            induced[messages[k]] = new
            result.last_change = result.transitions
            result.failed_to_final = result.failed
        state = after
        if progress is not None:
            progress(result)
        if induced and result.transitions - result.last_change >= settings.patience(len(evidence.pairs)):
            result.stopped = "stable"
            break
    else:
        result.stopped = "cap"
    result.rules = rule_list(induced, n)
    result.wall_seconds = time.perf_counter() - t0
    return result


class Curiosity:
    """Count-based, directed exploration from the agent's own memory of transitions.

    In a perceived state, an action not yet tried there is drawn uniformly (every action
    message is a candidate, legal or not: the agent knows nothing of the preconditions).
    Once all were tried, half of the choices (``balance``) are drawn uniformly among the
    actions tried least often in this state, and the other half take the action whose
    usual outcome from this state (the most frequent one remembered) is the least visited
    state (ties drawn uniformly). The directed half reaches rare configurations such as
    tall towers; the balanced half keeps retrying every action, so one noisy outcome (a
    tower knocked over during a pickup) does not hide where that action normally leads.

    Args:
        count: number of action messages.
        rng: the generator for the uniform draws.
        balance: share of count-based choices once every action was tried in a state.
    """

    def __init__(self, count: int, rng: np.random.Generator, balance: float = 0.5) -> None:
        self.count = count
        self.rng = rng
        self.balance = balance
        self.tried: dict[str, np.ndarray] = {}
        self.visits: dict[str, int] = {}
        self.outcomes: dict[tuple[str, int], Counter[str]] = {}

    def choose(self, message: str) -> int:
        """The index of the action to attempt in the state ``message``."""
        self.visits[message] = self.visits.get(message, 0) + 1
        counts = self.tried.setdefault(message, np.zeros(self.count, dtype=np.int64))
        if counts.min() == 0:
            options = np.flatnonzero(counts == 0)
        elif self.rng.random() < self.balance:
            options = np.flatnonzero(counts == counts.min())
        else:
            seen = np.array([self.visits.get(self.usual_outcome(message, k), 0) for k in range(self.count)])
            options = np.flatnonzero(seen == seen.min())
        k = int(options[int(self.rng.integers(len(options)))])
        counts[k] += 1
        return k

    def usual_outcome(self, message: str, k: int) -> str:
        """Where action ``k`` most often led from ``message`` (the state itself if never perceived)."""
        outcomes = self.outcomes.get((message, k))
        return outcomes.most_common(1)[0][0] if outcomes else message

    def remember(self, message: str, k: int, after: str) -> None:
        """Note where action ``k`` led from ``message``."""
        self.outcomes.setdefault((message, k), Counter())[after] += 1


def exhaustive_transitions(n: int, repeats: int = 3) -> list[Experience]:
    """Every (state, action) pair of the symbolic world ``repeats`` times, as transitions."""
    out = []
    for _ in range(repeats):
        for s in all_states(n):
            before = format_state_message(s, EXPLORATION_GOAL)
            for a in all_actions(n):
                legal = is_legal(s, a)
                after = format_state_message(successor(s, a), EXPLORATION_GOAL) if legal else before
                out.append(Experience(before, format_action_message(a, n), after, legal))
    return out


def report_dict(result: DiscoveryResult, meta: dict) -> dict:
    """The JSON report of a run (format version 1)."""
    rows = result.comparison()
    return {"format": "csql-sim discovery report", "version": 1, **meta, "blocks": result.n,
            "transitions": result.transitions, "failed_attempts": result.failed,
            "transitions_to_final_rules": result.last_change, "failed_to_final_rules": result.failed_to_final,
            "stopped": result.stopped,
            "restarts": result.restarts, "sim_seconds": round(result.sim_seconds, 3),
            "wall_seconds": round(result.wall_seconds, 3), "rules": len(result.rules),
            "equal_to_given": sum(r["equal"] for r in rows), "given": len(rows),
            "all_equal": result.equal_to_given, "perturbations": len(result.events), "comparison": rows}


def report_lines(result: DiscoveryResult) -> list[str]:
    """The printed report: the figures, then every given rule with its induced counterpart."""
    rows = result.comparison()
    same = sum(r["equal"] for r in rows)
    lines = [f"{result.transitions} transitions ({result.failed} failed attempts, {result.restarts} restarts), "
             f"rules final after {result.last_change} ({result.failed_to_final} failed); stopped: {result.stopped}",
             f"{result.sim_seconds:.1f} s simulated, {result.wall_seconds:.1f} s wall, "
             f"{len(result.events)} perturbations",
             f"{len(result.rules)} rules induced; {same} of {len(rows)} equal to the given ones"]
    for r in rows:
        mark = "=" if r["equal"] else "!"
        lines.append(f"  {mark} {r['kind']:<12} given {r['given']}   induced {r['induced'] or '-'}")
    return lines
