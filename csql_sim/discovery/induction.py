"""Rule induction: the R-classifiers of Figure 5 from observed transitions, with ``#``.

The evidence is a stream of :class:`Experience` records (the state message before, the
action message, the state message perceived after, and whether the primitive reported
success). For every action that has enough successes, :func:`induce_rules` returns

* an **add-delete rule**: condition ``S`` plus the action code in the action slot; output
  ``S`` plus, at every field whose value after the action is the same in the successes
  and differs from the posted message before it, that value; ``#`` elsewhere (the action
  slot is thereby reset to ``0``).
* a **precondition rule**: the most general condition that matches every state in which
  the action succeeded and no state in which it failed. Candidates are the positions whose
  character is the same in every success state; a failure state is excluded by a
  candidate where it has another character. The condition keeps a *smallest* set of
  candidates that excludes every failure state, found exhaustively by increasing size.
  Two documented biases make the answer unique:

  1. Candidates are first the positions the action's own add-delete rule writes (in the
     blocks world every precondition is deleted by its action: pickup(A) consumes clear(A),
     on(A) = t and the empty hand); only if these cannot exclude every failure are all
     constant positions used. Without this bias a 3-block world admits shorter but
     accidental conditions such as ``on(A) = b, on(C) = t`` for unstack(A,B) (C on the
     table is implied by A being clear on B only because there are three blocks). An
     action without a reliable add-delete rule gets no precondition rule either.
  2. Among equally small sets the first in the order of descending message position wins
     (the hand field before the on field before the clear field): positions that are
     logically equivalent, such as ``held = a`` and ``on(A) = 0``, cannot be separated by
     any data, and this fixed order is the paper's choice.

  With these, induction reproduces Figure 5 for n = 3 and the generated rules for n = 4
  and 5 string for string. For n = 2 it finds shorter, equivalent conditions (with two
  blocks, A on B already implies A clear and the hand empty).

Positions that never vary in any observed message (unused block slots, the goal during
exploration) are ``#`` by construction: they cannot exclude a failure or change.

Reliability (:class:`Reliability`): a rule needs at least ``min_successes`` successful
observations of its action, and must explain at least ``min_share`` of its observations;
a position enters an add-delete output only when at least ``min_share`` of the successes
agree. Only *refusals* are negative evidence: the guarded primitives refuse an action
whose preconditions they do not see before the arm moves, while a failure after the arm
moved (a missed grasp, a cube that slid off) says the action could start and is counted
for neither side (:attr:`Evidence.motion_failures`). A state counts as a failure state
when at least ``min_share`` of the successes and refusals in it were refusals. A
knocked-over tower thus stays a minority that creates no rule and corrupts none.

Disturbed transitions (:func:`disturbance`) count for neither side either: an outcome that
perception shows the attempted action cannot have caused (it was refused, yet the scene
changed; a cube other than the one the action message names changed its support; a
success that left the named cube elsewhere than the message's own hand or place) is
not evidence about the action. The test reads only the messages and the primitive's
status, never the simulator's perturbation schedule, so a replayed log is judged alike.
"""

from __future__ import annotations

import itertools
from collections import Counter, defaultdict
from dataclasses import dataclass

from csql_sim.core.classifiers.r_classifier import WILDCARD, AddDeleteRule, PreconditionRule, RClassifier
from csql_sim.core.state.message import (
    BLOCK_FIELD,
    PICK_FLAG,
    MessageLayout,
    action_messages,
    layout,
    parse_action_message,
)


@dataclass(frozen=True)
class Experience:
    """One attempted action as the agent saw it.

    Attributes:
        before: the state message perceived before (action slot ``0``).
        action: the action message attempted.
        after: the state message perceived afterwards (action slot ``0``).
        ok: the primitive's status: True when it reported success.
        reason: the primitive's reason for a failure, else empty.
        refused: for a failure, whether the primitive refused before moving (its guard saw
            that the action cannot start); None means "every failure is a refusal".
    """

    before: str
    action: str
    after: str
    ok: bool
    reason: str = ""
    refused: bool | None = None

    @property
    def is_refusal(self) -> bool:
        """A failure that says the preconditions do not hold (not a failed motion)."""
        return not self.ok and self.refused is not False


@dataclass(frozen=True)
class Reliability:
    """When an induced rule is trusted (see the module docstring)."""

    min_successes: int = 3  # successful observations of the action before any rule is made
    min_share: float = 0.8  # share of observations a rule (or an output position) must agree with


RELIABILITY = Reliability()


@dataclass(frozen=True)
class InducedRules:
    """The two R-classifiers of one action (either may be None: not yet reliable)."""

    action: str
    precondition: PreconditionRule | None
    add_delete: AddDeleteRule | None

    def strings(self) -> tuple[tuple[str, str] | None, ...]:
        """The rules as (condition, action) strings, for comparison."""
        return tuple(None if r is None else (r.condition, r.action) for r in (self.precondition, self.add_delete))


class Evidence:
    """Counts of the observed transitions, per action message.

    Args:
        n: number of blocks (fixes the message layout).
    """

    def __init__(self, n: int) -> None:
        self.n = n
        self.layout = layout(n)
        self.outcomes: dict[str, dict[str, list[int]]] = defaultdict(lambda: defaultdict(lambda: [0, 0]))
        self.effects: dict[str, Counter[tuple[str, str]]] = defaultdict(Counter)
        self.varying: set[int] = set()
        self.pairs: set[tuple[str, str]] = set()
        self._reference: str | None = None
        self.count = 0
        self.motion_failures = 0
        self.disturbed = 0

    def add(self, t: Experience) -> str:
        """Record one transition; returns why it is disturbed (then it counts for neither side), else ""."""
        self.count += 1
        self.pairs.add((t.before, t.action))
        reason = disturbance(t, self.layout)
        if reason:
            self.disturbed += 1
            return reason
        if t.ok or t.is_refusal:
            self.outcomes[t.action][t.before][0 if t.ok else 1] += 1
        else:
            self.motion_failures += 1  # the action could start; it says nothing about preconditions
        posted = self.posted(t.before, t.action)
        for message in (t.before, t.after, posted):
            self._note_variation(message)
        if t.ok:
            self.effects[t.action][(posted, t.after)] += 1
        return ""

    def posted(self, before: str, action: str) -> str:
        """``before`` with the action's code in its action slot (what the add-delete rules read)."""
        w = self.layout.action_width
        return before[0] + action[1 : 1 + w] + before[1 + w :]

    def _note_variation(self, message: str) -> None:
        if self._reference is None:
            self._reference = message
            return
        for p, (a, b) in enumerate(zip(self._reference, message, strict=True)):
            if a != b:
                self.varying.add(p)


def disturbance(t: Experience, lay: MessageLayout) -> str:
    """Why perception shows an outcome the attempted action cannot have caused, else "".

    The action message names the cube it moves, the motion (pick or put) and the place
    it takes the cube from or puts it onto. What the action can cause follows from that
    and the primitive's status alone:

    * a refusal stops the arm before it moves: the scene after must be the scene before;
    * no other cube changes its support (a cube that moved without being named was
      pushed, by a nudge or by the arm's own elbow);
    * a success leaves the named cube where the message says: held after a pick, on the
      named place with an empty hand after a put.

    A failure after the arm moved (a missed grasp, a cube that slid off) is already no
    evidence either way and is not judged here.
    """
    if t.is_refusal:
        return "" if t.after == t.before else "the scene changed although the action was refused"
    if not t.ok:
        return ""
    w, on, held = lay.action_width, lay.on_start, lay.held_pos
    flag = 1 + w + BLOCK_FIELD  # the action message: A, code, six zeros, motion flag, cube, place
    moved, place = t.action[flag + 4], t.action[flag + 5]
    index = ord(moved) - ord("a")
    for i in range(BLOCK_FIELD):
        if i != index and t.before[on + i] != t.after[on + i]:
            return f"{'ABCDEF'[i]} changed its support, the action moves {moved.upper()}"
    if t.action[flag : flag + 4] == PICK_FLAG:
        return "" if t.after[held] == moved else f"{moved.upper()} is not held after a successful pick"
    if t.after[on + index] != place or t.after[held] != "0":
        return f"{moved.upper()} is not on {place} after a successful put"
    return ""


def _blank(length: int) -> list[str]:
    return ["S"] + [WILDCARD] * (length - 1)


def _minimal_cover(candidates: list[int], failures: list[set[int]]) -> tuple[int, ...] | None:
    """The first smallest subset of ``candidates`` (in their order) meeting every failure's set."""
    for size in range(len(candidates) + 1):
        for combo in itertools.combinations(candidates, size):
            chosen = set(combo)
            if all(f & chosen for f in failures):
                return combo
    return None


def induce_precondition(ev: Evidence, action: str, changed: tuple[int, ...] = (),
                        rel: Reliability = RELIABILITY) -> PreconditionRule | None:
    """The precondition rule of ``action``, or None while the evidence is not enough or inconsistent.

    Args:
        ev: the evidence.
        action: the action message.
        changed: the positions the action's add-delete rule writes; tried first as candidates.
        rel: the reliability thresholds.
    """
    outcomes = ev.outcomes.get(action, {})
    positives = [s for s, (ok, bad) in outcomes.items() if ok and bad / (ok + bad) < rel.min_share]
    negatives = [s for s, (ok, bad) in outcomes.items() if ok + bad and bad / (ok + bad) >= rel.min_share]
    if sum(outcomes[s][0] for s in positives) < rel.min_successes:
        return None
    first = positives[0]
    constant = [p for p in sorted(ev.varying, reverse=True) if p > 0 and all(s[p] == first[p] for s in positives)]
    cover = None
    for candidates in ([p for p in constant if p in changed], constant):
        excluders = [{p for p in candidates if s[p] != first[p]} for s in negatives]
        cover = _minimal_cover(candidates, excluders)
        if cover is not None:
            break
    if cover is None:
        return None
    total = sum(ok + bad for ok, bad in outcomes.values())
    explained = sum(outcomes[s][0] for s in positives) + sum(outcomes[s][1] for s in negatives)
    if explained < rel.min_share * total:
        return None
    pattern = _blank(len(first))
    for p in cover:
        pattern[p] = first[p]
    return PreconditionRule("".join(pattern), action)


def _cut(message: str, field: range) -> str:
    return message[field.start : field.stop]


def induce_add_delete(ev: Evidence, action: str, rel: Reliability = RELIABILITY) -> AddDeleteRule | None:
    """The add-delete rule of ``action``, or None while its successes are too few or disagree."""
    pairs = ev.effects.get(action)
    total = sum(pairs.values()) if pairs else 0
    if total < rel.min_successes:
        return None
    length = len(next(iter(pairs))[0])
    w = ev.layout.action_width
    output = _blank(length)
    for field in [range(1, 1 + w)] + [range(p, p + 1) for p in range(1 + w, length)]:
        if not any(p in ev.varying for p in field):
            continue
        values: Counter[str] = Counter()
        for (_, after), k in pairs.items():
            values[_cut(after, field)] += k
        v, same = values.most_common(1)[0]
        changed = sum(k for (posted, _), k in pairs.items() if _cut(posted, field) != v)
        if same >= rel.min_share * total and changed >= rel.min_share * total:
            output[field.start : field.stop] = list(v)
    condition = "S" + action[1 : 1 + w] + WILDCARD * (length - 1 - w)
    rule = AddDeleteRule(condition, "".join(output))
    right = sum(k for (posted, after), k in pairs.items() if rule.apply(posted) == after)
    if right < rel.min_share * total:
        return None
    return rule


def induce_action(ev: Evidence, action: str, rel: Reliability = RELIABILITY) -> InducedRules:
    """Both rules of one action: the add-delete rule first, its written positions guide the precondition."""
    post = induce_add_delete(ev, action, rel)
    if post is None:  # no reliable effect yet: no precondition either (its candidates are unknown)
        return InducedRules(action, None, None)
    changed = tuple(p for p, ch in enumerate(post.output) if p > 0 and ch != WILDCARD)
    return InducedRules(action, induce_precondition(ev, action, changed, rel), post)


def rule_list(induced: dict[str, InducedRules], n: int) -> list[RClassifier]:
    """The induced R-classifiers in the usual order: preconditions, then add-delete rules."""
    order = [m for m in action_messages(n) if m in induced]
    pre = [induced[m].precondition for m in order if induced[m].precondition is not None]
    post = [induced[m].add_delete for m in order if induced[m].add_delete is not None]
    return pre + post


def induce_rules(transitions, n: int, rel: Reliability = RELIABILITY) -> list[RClassifier]:
    """The R-classifiers induced from an iterable of :class:`Experience` records."""
    ev = Evidence(n)
    for t in transitions:
        parse_action_message(t.action, n)  # reject foreign action messages early
        ev.add(t)
    return rule_list({a: induce_action(ev, a, rel) for a in ev.outcomes}, n)
