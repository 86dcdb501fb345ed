"""Offline compaction: a trained rule base becomes a small default hierarchy of ``#`` Q-classifiers.

The input is a rule base in the index form (one Q-classifier per state, goal and legal
action, from ``csql-sim train``). For every (state, goal) pair its Q-classifiers say which
actions are greedy (the highest Q-value, ties kept: every action within :data:`TOLERANCE`
of the best). The output is an ordered list of goal-form Q-classifiers
(:mod:`csql_sim.core.state.goal_message`) whose default hierarchy
(:mod:`csql_sim.core.policies.default_hierarchy`: the first matching classifier whose action is a
candidate acts) picks a greedy action of the input in every pair the input decides. So the
compacted base plans exactly as well as the input did; no distance is consulted here.

The search is a greedy decision list (Rivest 1987) over the messages of every pair, with
bitsets over pairs:

1. **grow**: repeatedly add the rule (a condition of ``(position, character)`` literals and
   an action) that decides the most still-open pairs while being right on every open pair
   it matches; per action a beam search adds literals top-down; a lazy priority queue
   re-searches only the action on top (a rule's reach can only shrink as pairs close);
2. **generalize**: drop any literal whose removal keeps the whole list right;
3. **prune**: drop any rule whose removal keeps the whole list right;

repeating 2-3 until nothing changes; then

4. **refine**: the list's rules with up to :data:`DROP_AT_MOST` literals dropped form a pool,
   and :func:`decision_list` builds a new list from it (a general rule that is wrong on
   some open pair waits until earlier rules have closed those pairs: it becomes a
   default), pruned as in 2-3; kept while it is shorter.

Early rules are specific exceptions, late ones the general defaults.
"""

from __future__ import annotations

import heapq
import itertools
import os
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.files.rulebase import RuleBase, load
from csql_sim.core.files.rulebase_npz import to_arrays
from csql_sim.core.model.world_model import WorldModel
from csql_sim.core.state.goal_message import INDEX_FORM, WILDCARD, GoalForm, form_of
from csql_sim.core.state.goal_message_index import pair_messages
from csql_sim.core.state.message import action_messages, layout
from csql_sim.core.state.message_index import action_indices, base36_column, lookup, state_bodies
from csql_sim.core.state.world import BlocksWorld
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.provenance import file_sha256, provenance

TOLERANCE = 1e-9
"""Q-values within this of a pair's best count as greedy (ties of a converged table)."""
BEAM = 6
MAX_LITERALS = 14
REFINE_ROUNDS = 5
"""Rounds of re-ordering: the list's rules with literals dropped, as a pool for :func:`decision_list`."""
DROP_AT_MOST = 3


def greedy_sets(rulebase: RuleBase, value: str = "q") -> tuple[np.ndarray, np.ndarray]:
    """The input's greedy actions: ``allowed[pair, action]`` and the best value per pair (NaN: none).

    Pairs are ``state * S + goal``; only index-form Q-classifiers count.
    """
    n, world = rulebase.blocks, BlocksWorld.of(rulebase.blocks)
    count, lay = len(world.states), layout(n)
    a = to_arrays(rulebase)
    is_q = np.flatnonzero(a["kind"] == b"Q")
    conds = a["condition"][is_q]
    state = lookup(conds, 0, lay.goal_start, state_bodies(n))
    goal = base36_column(conds, lay.goal_start, lay.length)
    act = lookup(a["action"][is_q], 0, lay.length, action_indices(n))
    ok = (state >= 0) & (goal < count) & (act >= 0)
    key, q, act = (state * count + goal)[ok], a[value][is_q][ok], act[ok]
    best = np.full(count * count, -np.inf)
    np.maximum.at(best, key, q)
    allowed = np.zeros((count * count, len(world.actions)), bool)
    allowed[key, act] = q >= best[key] - TOLERANCE
    best[~np.isfinite(best)] = np.nan
    return allowed, best


def _bits(mask: np.ndarray) -> int:
    """A bool array as a Python integer bitset (bit i = element i)."""
    return int.from_bytes(np.packbits(mask, bitorder="little").tobytes(), "little")


@dataclass
class Rule:
    """A rule of the growing list: literals (position, character code) and an action index."""

    literals: tuple[tuple[int, int], ...]
    action: int
    bits: int | None = field(default=None, compare=False, repr=False)  # the cover, once computed


class Problem:
    """The pairs, their messages and greedy sets as bitsets."""

    def __init__(self, form: GoalForm, allowed: np.ndarray, legal: np.ndarray) -> None:
        count = legal.shape[0]
        messages = pair_messages(form)
        informative = allowed.any(axis=1)
        informative[np.arange(count) * (count + 1)] = False
        self.todo = _bits(informative)
        state_of = np.repeat(np.arange(count), count)
        self.legal = [_bits(legal[state_of, a]) for a in range(legal.shape[1])]
        self.allowed = [_bits(allowed[:, a]) for a in range(legal.shape[1])]
        self.literal: dict[tuple[int, int], int] = {}
        rows = messages[informative]
        for pos in range(messages.shape[1]):
            values = np.unique(rows[:, pos])
            if len(values) > 1:
                for v in values.tolist():
                    self.literal[(pos, v)] = _bits(messages[:, pos] == v)

    def cover(self, rule: Rule) -> int:
        """The pairs a rule matches where its action is a candidate (kept on the rule)."""
        if rule.bits is None:
            bits = self.legal[rule.action]
            for lit in rule.literals:
                bits &= self.literal[lit]
            rule.bits = bits
        return rule.bits

    def valid(self, rules: list[Rule], open_: int | None = None) -> bool:
        """Whether the list, first match deciding, picks an allowed action in every informative pair.

        ``open_``: the pairs still open before the list (default: every informative pair).
        """
        open_ = self.todo if open_ is None else open_
        for rule in rules:
            hit = self.cover(rule) & open_
            if hit & ~self.allowed[rule.action]:
                return False
            open_ &= ~hit
        return open_ == 0

    def best_rule(self, action: int, open_: int) -> tuple[int, Rule | None]:
        """Beam search for the literals that decide the most open pairs with no wrong decision."""
        base = self.legal[action] & open_
        pos, neg = base & self.allowed[action], base & ~self.allowed[action]
        if not pos:
            return 0, None
        best: tuple[int, Rule | None] = (0, None)
        if not neg:
            return pos.bit_count(), Rule((), action)
        beam: list[tuple[tuple[int, int], ...]] = [()]
        covers = {(): base}
        for _ in range(MAX_LITERALS):
            scored = []
            for lits in beam:
                bits, used = covers[lits], {p for p, _ in lits}
                for lit, lbits in self.literal.items():
                    if lit[0] in used:
                        continue
                    new = bits & lbits
                    p = (new & pos).bit_count()
                    if p <= best[0]:
                        continue
                    key = tuple(sorted((*lits, lit)))
                    wrong = (new & neg).bit_count()
                    if wrong == 0:
                        best = (p, Rule(key, action))
                    else:
                        covers[key] = new
                        scored.append((p / (p + wrong), p, key))
            scored = [s for s in scored if s[1] > best[0]]
            if not scored:
                break
            scored.sort(reverse=True)
            beam = list(dict.fromkeys(s[2] for s in scored))[:BEAM]
        return best


def grow(problem: Problem, on_rule: Callable[[int], None] | None = None) -> list[Rule]:
    """Greedy decision list: the rule deciding the most open pairs, rightly, until none is open."""
    open_ = problem.todo
    rules: list[Rule] = []
    heap: list[tuple[int, int]] = [(-(problem.legal[a] & open_).bit_count(), a) for a in range(len(problem.legal))]
    heapq.heapify(heap)
    while open_:
        if not heap:
            raise CsqlError("compaction found no rule for the open pairs (the input decides a pair "
                            "with no legal action)")
        _, a = heapq.heappop(heap)
        score, rule = problem.best_rule(a, open_)
        if rule is None:
            continue
        if heap and score < -heap[0][0]:
            heapq.heappush(heap, (-score, a))
            continue
        rules.append(rule)
        open_ &= ~problem.cover(rule)
        heapq.heappush(heap, (-score, a))  # stale; re-searched when on top
        if on_rule is not None:
            on_rule(open_.bit_count())
    return rules


def simplify(problem: Problem, rules: list[Rule]) -> list[Rule]:
    """Drop literals, then whole rules, while the list stays right; until nothing changes."""
    changed = True
    while changed:
        changed = False
        before = problem.todo  # the pairs open before rule k
        for k, rule in enumerate(rules):
            for lit in rule.literals:
                trial = Rule(tuple(x for x in rule.literals if x != lit), rule.action)
                if problem.valid([trial, *rules[k + 1:]], before):
                    rules[k] = rule = trial
                    changed = True
            before &= ~problem.cover(rule)
        opens = [problem.todo]
        for rule in rules:
            opens.append(opens[-1] & ~problem.cover(rule))
        for k in range(len(rules) - 1, -1, -1):  # only later rules change: opens[k] stays right
            if problem.valid(rules[k + 1:], opens[k]):
                del rules[k]
                changed = True
    return rules


def decision_list(problem: Problem, rules: list[Rule]) -> list[Rule]:
    """Greedy over the population: the rule right on every open pair it matches that decides the most."""
    open_ = problem.todo
    covers = [problem.cover(r) for r in rules]
    heap = [(-(c & open_).bit_count(), k) for k, c in enumerate(covers)]
    heapq.heapify(heap)
    out: list[Rule] = []
    parked: list[int] = []  # wrong on some open pair: retried once more pairs are closed
    while heap and open_:
        _, k = heapq.heappop(heap)
        hit = covers[k] & open_
        if not hit:
            continue
        if hit & ~problem.allowed[rules[k].action]:
            parked.append(k)
            continue
        score = hit.bit_count()
        if heap and score < -heap[0][0]:
            heapq.heappush(heap, (-score, k))
            continue
        out.append(rules[k])
        open_ &= ~hit
        for j in parked:
            heapq.heappush(heap, (-(covers[j] & open_).bit_count(), j))
        parked = []
    while open_:  # covering at the end: a pair no actor decides rightly gets its own actor
        key = (open_ & -open_).bit_length() - 1
        action = next(a for a, bits in enumerate(problem.allowed) if bits >> key & 1 and problem.legal[a] >> key & 1)
        lits = tuple((p, v) for (p, v), bits in problem.literal.items() if bits >> key & 1)
        out.append(Rule(lits, action))
        open_ &= ~problem.cover(out[-1])
    return out


def _subsets(literals: tuple[tuple[int, int], ...]) -> list[tuple[tuple[int, int], ...]]:
    """The literal sets to drop from a rule for the refinement pool: up to :data:`DROP_AT_MOST` of them."""
    return [drop for k in range(DROP_AT_MOST + 1) for drop in itertools.combinations(literals, k)]


def condition_of(rule: Rule, form: GoalForm) -> str:
    """The goal-form condition of a rule: ``#`` except its literals (tags written out)."""
    chars = [WILDCARD] * form.length
    chars[0], chars[form.tag_pos] = "S", "G"
    for pos, code in rule.literals:
        chars[pos] = chr(code)
    return "".join(chars)


def compact(rulebase: RuleBase, form: GoalForm | None = None,
            on_rule: Callable[[int], None] | None = None) -> tuple[list[QClassifier], dict]:
    """The default hierarchy of goal-form Q-classifiers that plans as ``rulebase``'s greedy policy does.

    Args:
        rulebase: a trained index-form rule base (its R-classifiers, if any, name the candidates).
        form: the goal form to write (default: all detectors).
        on_rule: called with the number of open pairs after each rule is grown (progress).

    Returns:
        The Q-classifiers in list order, and facts for the output's meta.
    """
    n = rulebase.blocks
    form = form or GoalForm(n)
    if form.n != n:
        raise CsqlError(f"the form is for {form.n} blocks, the rule base for {n}")
    rs = [c for c in rulebase.classifiers if not isinstance(c, QClassifier)]
    model = WorldModel(rs, n) if rs else WorldModel.for_blocks(n)
    value = rulebase.meta.get("value", "q")
    allowed, best = greedy_sets(rulebase, value if value in ("q", "strength") else "q")
    legal = model.table.next_state >= 0
    problem = Problem(form, allowed, legal)
    grown = grow(problem, on_rule)
    rules = simplify(problem, list(grown))
    for _ in range(REFINE_ROUNDS):  # a default hierarchy from the list's rules and their generalizations
        pool = [Rule(tuple(x for x in r.literals if x not in drop), r.action)
                for r in rules for drop in _subsets(r.literals)]
        refined = simplify(problem, decision_list(problem, pool))
        if len(refined) >= len(rules):
            break
        rules = refined
    qs = _classifiers(problem, rules, form, best)
    facts = {"pairs_decided": problem.todo.bit_count(), "grown": len(grown), "value": value,
             "action_selection": "the first Q-classifier (list order) that matches and proposes a candidate action"}
    return qs, facts


def _classifiers(problem: Problem, rules: list[Rule], form: GoalForm, best: np.ndarray) -> list[QClassifier]:
    """The rules as Q-classifiers; q is the input's mean best value over the pairs each decides."""
    messages = action_messages(form.n)
    open_, out = problem.todo, []
    for rule in rules:
        hit = problem.cover(rule) & open_
        open_ &= ~hit
        idx = np.flatnonzero(np.unpackbits(np.frombuffer(hit.to_bytes((hit.bit_length() + 7) // 8 or 1, "little"),
                                                         np.uint8), bitorder="little"))
        q = float(np.nanmean(best[idx])) if len(idx) else 0.0
        out.append(QClassifier(condition_of(rule, form), messages[rule.action], q=q, strength=1.0))
    return out


def generalize(path: str | os.PathLike, detectors: tuple[str, ...] | None = None,
               progress: bool = False) -> RuleBase:
    """``csql-sim generalize``: read a trained index-form rule file and compact it (:func:`compact`).

    The result's meta records the goal form, the input (path, sha256, form, Q-classifier
    count) and the action-selection rule.

    Raises:
        CsqlError: for an unreadable file, or one already in the goal form.
    """
    from tqdm import tqdm

    rulebase = load(path, progress=progress)
    if form_of(rulebase.meta, rulebase.blocks, os.fspath(path)) is not None:
        raise CsqlError(f"rule file {os.fspath(path)!r} is already in the goal form; give a trained "
                        "index-form rule file")
    form = GoalForm(rulebase.blocks) if detectors is None else GoalForm(rulebase.blocks, detectors)
    inputs = sum(isinstance(c, QClassifier) for c in rulebase.classifiers)
    if not inputs:
        raise CsqlError(f"rule file {os.fspath(path)!r} holds no Q-classifier to compact")
    with tqdm(desc="open pairs", unit="pair", disable=not progress, leave=False, delay=1.0) as bar:
        def on_rule(open_pairs: int) -> None:
            if bar.total is None:
                bar.total = open_pairs + 1
            bar.n = bar.total - open_pairs
            bar.refresh()

        qs, facts = compact(rulebase, form, on_rule)
    source = {"path": os.fspath(path), "sha256": file_sha256(path), "form": INDEX_FORM,
              "q_classifiers": inputs, "method": rulebase.meta.get("method")}
    meta = {**form.meta(), "method": "compaction", "source": source, **facts,
            "provenance": provenance(rules=os.fspath(path), detectors=list(form.detectors))}
    return RuleBase(blocks=rulebase.blocks, classifiers=list(qs), meta=meta)

