"""Rule discovery: the agent plays with the blocks and induces its own R-classifiers.

From the perceived state the agent attempts an action drawn uniformly from *all* action
messages of the world (not only the legal ones), executes it, perceives again and records
a :class:`~csql_sim.discovery.induction.Experience`. After every transition the rules of the
attempted action are induced again (:mod:`csql_sim.discovery.induction`). Exploration stops
when the rule set has not changed for ``Exploration.patience`` transitions (1000, or twice
the number of distinct (state, action) pairs tried so far if that is more: 1000 for n = 3,
about 8000 for n = 4) *and* no (state, action) pair is open (:meth:`Curiosity.open_actions`:
an action that gave no evidence in a visited state, a configuration the induced rules
predict but the agent never perceived, an action that succeeded but has no reliable rules
yet), or after ``max_transitions``. Actions are chosen by :class:`Curiosity` (untried
actions first, then half balanced, half along the agent's model towards the nearest open
pair). A transition whose outcome the action cannot have caused (judged from perception,
:func:`~csql_sim.discovery.induction.disturbance`) is kept in the log but teaches nothing.

The world is anything with the :class:`~csql_sim.discovery.world.ExplorableWorld` protocol:
:class:`~csql_sim.discovery.world.SymbolicWorld` (an illegal action fails and changes nothing;
``perturb`` knocks a tower top onto the table now and then), or the simulated arm
(:mod:`csql_sim.sim.control.exploration`). State messages use goal code 0 throughout (exploration
has no goal), so the goal position never varies and induces nothing.
"""

from __future__ import annotations

import time
from collections import Counter, deque
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from csql_sim.core.classifiers.r_classifier import PreconditionRule, RClassifier, matches, r_classifiers
from csql_sim.core.state.message import action_messages, format_action_message, format_state_message
from csql_sim.core.state.world import all_actions, all_states, is_legal, successor
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
    disturbed: int = 0  # transitions whose outcome the action cannot have caused (evidence for neither side)
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
    """Explore ``world`` (actions chosen by :class:`Curiosity`) and induce its R-classifiers.

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
    curiosity = Curiosity(messages, rng, Evidence(n))
    induced, evidence = curiosity.rules, curiosity.evidence
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
        _learn(record, k, curiosity, result, settings.reliability)
        if keep_log:
            result.log.append(record)
        state = after
        if progress is not None:
            progress(result)
        if (induced and result.transitions - result.last_change >= settings.patience(len(evidence.pairs))
                and not curiosity.open_pairs()):
            result.stopped = "stable"
            break
    else:
        result.stopped = "cap"
    result.rules = rule_list(induced, n)
    result.wall_seconds = time.perf_counter() - t0
    return result


TRY_CAP = 3  # tries of a (state, action) pair after which it counts as explored, evidence or not
RETRY_CAP = 10  # tries of a pair that succeeded while its action has no complete rule pair yet


def _learn(record: Experience, k: int, curiosity: Curiosity, result: DiscoveryResult, rel: Reliability) -> None:
    """Add one transition to the evidence and the agent's memory, and induce its action's rules again."""
    disturbed = curiosity.evidence.add(record)
    curiosity.remember(record.before, k, record.after, record.ok, not disturbed and (record.ok or record.is_refusal))
    result.transitions += 1
    result.disturbed += bool(disturbed)
    result.failed += not record.ok
    new = induce_action(curiosity.evidence, record.action, rel)
    old = curiosity.rules.get(record.action)
    if old is None or old.strings() != new.strings():
        curiosity.learned(record.action, new)
        result.last_change = result.transitions
        result.failed_to_final = result.failed


class Curiosity:
    """Count-based exploration, directed by the agent's own memory and induced rules.

    In a perceived state, an action that gave no evidence there yet is drawn uniformly
    (every action message is a candidate, legal or not: the agent knows nothing of the
    preconditions). Once all did, half of the choices (``balance``) are drawn uniformly
    among the actions tried least often in this state; the other half take the first step
    of a shortest path to the nearest *open* (state, action) pair (:meth:`open_actions`) over
    the agent's model (remembered outcomes, else the induced rules' predictions), or, with
    nothing open or reachable, the action whose usual outcome is the least visited state.

    Only undisturbed transitions shape the memory: an outcome the action did not cause
    (:func:`~csql_sim.discovery.induction.disturbance`) neither hides nor invents a state.

    Args:
        messages: the action messages (index = action).
        rng: the generator for the uniform draws.
        evidence: the run's evidence (its message layout places the action code).
        balance: share of count-based choices once every action gave evidence in a state.
    """

    def __init__(self, messages: tuple[str, ...], rng: np.random.Generator, evidence: Evidence,
                 balance: float = 0.5) -> None:
        self.messages = messages
        self.count = len(messages)
        self.rng = rng
        self.evidence = evidence
        self.balance = balance
        self.rules: dict[str, InducedRules] = {}  # the induced rules, kept current by explore()
        self.tried: dict[str, np.ndarray] = {}  # attempts per state and action
        self.informed: dict[str, np.ndarray] = {}  # attempts that gave evidence (a success or a refusal)
        self.succeeded: dict[str, np.ndarray] = {}  # undisturbed successes
        self.visits: dict[str, int] = {}
        self.outcomes: dict[tuple[str, int], Counter[str]] = {}
        self.remembered: dict[str, set[int]] = {}  # per state, the actions with a remembered success
        self.version = 0  # counts changes of the induced rules
        self._predictions: dict[str, tuple[int, dict[int, str]]] = {}

    def _row(self, table: dict[str, np.ndarray], message: str) -> np.ndarray:
        return table.setdefault(message, np.zeros(self.count, dtype=np.int64))

    def choose(self, message: str) -> int:
        """The index of the action to attempt in the state ``message``."""
        self.visits[message] = self.visits.get(message, 0) + 1
        counts = self._row(self.tried, message)
        fresh = (self._row(self.informed, message) == 0) & (counts < TRY_CAP)
        if fresh.any():
            options = np.flatnonzero(fresh)
        elif self.rng.random() < self.balance:
            options = np.flatnonzero(counts == counts.min())
        else:
            step = self.toward_open(message)
            if step is not None:
                options = np.array([step])
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

    def remember(self, message: str, k: int, after: str, ok: bool, evidence: bool) -> None:
        """Note an attempt's outcome; ``evidence``: it counted as a success or a refusal."""
        if not evidence:
            return
        self._row(self.informed, message)[k] += 1
        if ok:
            self._row(self.succeeded, message)[k] += 1
            self.outcomes.setdefault((message, k), Counter())[after] += 1
            self.remembered.setdefault(message, set()).add(k)

    def learned(self, action: str, rules: InducedRules) -> None:
        """Take the newly induced rules of ``action`` (the model's predictions are computed afresh)."""
        self.rules[action] = rules
        self.version += 1

    def successors(self, message: str) -> dict[int, str]:
        """The successors the induced rules predict in ``message``, by action (only actions they accept)."""
        cached = self._predictions.get(message)
        if cached is None or cached[0] != self.version:
            out = {}
            for k, m in enumerate(self.messages):
                rules = self.rules.get(m)
                if rules is not None and rules.precondition is not None and rules.add_delete is not None \
                        and matches(rules.precondition.condition, message):
                    out[k] = rules.add_delete.apply(self.evidence.posted(message, m))
            cached = self._predictions[message] = (self.version, out)
        return cached[1]

    def predicted(self, message: str, k: int) -> str | None:
        """The successor the induced rules predict for action ``k`` in ``message``, None if they predict none."""
        return self.successors(message).get(k)

    def open_actions(self, message: str, incomplete: np.ndarray | None = None) -> list[int]:
        """The actions whose pair with the visited state ``message`` still asks to be tried.

        Open is a pair that gave no evidence yet (fewer than ``TRY_CAP`` tries); a pair
        whose predicted successor was never visited (a configuration the rules say exists;
        closed after ``TRY_CAP`` tries that did not get there); and a pair in which the
        action succeeded while it has no complete, reliable rule pair yet (closed after
        ``RETRY_CAP`` tries).

        Args:
            message: a visited state.
            incomplete: per action, whether its rule pair is incomplete (computed if None).
        """
        if incomplete is None:
            incomplete = self.incomplete()
        tried, informed = self._row(self.tried, message), self._row(self.informed, message)
        young = tried < TRY_CAP
        out = (young & (informed == 0)) | ((tried < RETRY_CAP) & (self._row(self.succeeded, message) > 0) & incomplete)
        for k, nxt in self.successors(message).items():
            out[k] |= bool(young[k]) and nxt not in self.visits
        return [int(k) for k in np.flatnonzero(out)]

    def incomplete(self) -> np.ndarray:
        """Per action: True while it lacks a reliable precondition or add-delete rule."""
        rules = [self.rules.get(m) for m in self.messages]
        return np.array([r is None or r.precondition is None or r.add_delete is None for r in rules])

    def open_pairs(self) -> dict[str, list[int]]:
        """Every open pair (:meth:`open_actions`), by state."""
        incomplete = self.incomplete()
        out: dict[str, list[int]] = {}
        for message in self.tried:
            ks = self.open_actions(message, incomplete)
            if ks:
                out[message] = ks
        return out

    def edges(self, message: str) -> dict[int, str]:
        """Where each action leads from ``message`` in the agent's model: remembered, else predicted."""
        out = dict(self.successors(message))
        for k in self.remembered.get(message, ()):
            out[k] = self.usual_outcome(message, k)
        return {k: nxt for k, nxt in out.items() if nxt != message}

    def toward_open(self, start: str) -> int | None:
        """The first action of a shortest path in the model to an open pair, then its action."""
        targets = self.open_pairs()
        first: dict[str, int | None] = {start: None}
        queue = deque([start])
        while queue:
            s = queue.popleft()
            if s in targets:
                return targets[s][0] if first[s] is None else first[s]
            for k, nxt in sorted(self.edges(s).items()):
                if nxt not in first:
                    first[nxt] = k if first[s] is None else first[s]
                    queue.append(nxt)
        return None


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
            "stopped": result.stopped, "disturbed_transitions": result.disturbed,
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
             f"{len(result.events)} perturbations, {result.disturbed} disturbed transitions",
             f"{len(result.rules)} rules induced; {same} of {len(rows)} equal to the given ones"]
    for r in rows:
        mark = "=" if r["equal"] else "!"
        lines.append(f"  {mark} {r['kind']:<12} given {r['given']}   induced {r['induced'] or '-'}")
    return lines
