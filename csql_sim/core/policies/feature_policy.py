"""Lifted Q-classifiers over generated features: the greedy policy, and their file.

A classifier learned over generated features (:mod:`csql_sim.core.features`) has the lines
of :mod:`~csql_sim.core.policies.lifted_policy`, one condition character per **literal** the
file names (``x:all(star(on),eq(on,on_g))`` reads "?x ∈ ∀on*.(on = on_g)"; see
:mod:`~csql_sim.core.features.move_features`). The file keeps only the literals some
classifier tests, and the PDDL domain whose predicates they read, so it plans on its own.

:class:`FeaturePolicy` binds ``?x`` and ``?d`` to every legal move, evaluates the literals on
the state and on the state after each move (one move of lookahead) and takes the move of
least advantage of its most specific matching classifier (ties: the first in move order).
The features read the goal as it is (a goal that holds a block included); the policy knows
no other concept of the task. A move is executed as its pick, then the put of the move
chosen (in the move domain the step between them is not a state; in the four-operator
domain the put is the one chosen with the move, so a pick is never undone by its own put).
Only holding a block at the start is a put chosen holding it. An action that reaches the
goal is taken (one action of lookahead: the reward of the task's last action).
"""

from __future__ import annotations

import json
from collections.abc import Iterable

import numpy as np

from csql_sim.core.features.formulation import BUILTIN, Formulation, parse_formulation
from csql_sim.core.features.move_features import Literal, literal_values, parse_literal, parsed
from csql_sim.core.policies.contract import Policy
from csql_sim.core.policies.lifted_classifier import (
    LIFTED_Q_FORMAT,
    LIFTED_Q_VERSION,
    LiftedPolicyError,
    LiftedQClassifier,
    classifier_lines,
    most_specific,
)
from csql_sim.core.state.moves import Move, last_action, pick_action, put_action
from csql_sim.core.state.world import Action, State, successor
from csql_sim.infra.errors import CsqlError

MAX_LITERALS = 512
"""The most literals a file may name."""


class FeaturePolicy(Policy):
    """Greedy policy over lifted Q-classifiers on generated features (module docstring)."""

    name = "rules"
    blocks: int | None = None

    def __init__(self, classifiers: Iterable[LiftedQClassifier], literals: tuple[Literal, ...],
                 form: Formulation, domain: str, meta: dict | None = None, tie: Literal | None = None) -> None:
        self.classifiers = tuple(classifiers)
        self.literals, self.form, self.domain, self.tie = literals, form, domain, tie
        self.meta = dict(meta or {})
        self._match: dict[tuple[bytes, str], LiftedQClassifier | None] = {}
        self._chosen: tuple[State, State, Move] | None = None

    def classifier_for(self, bits: np.ndarray, kind: str) -> LiftedQClassifier | None:
        """The most specific classifier matching a move's literal values (remembered)."""
        key = (bits.tobytes(), kind)
        if key not in self._match:
            self._match[key] = most_specific(self.classifiers, tuple(int(b) for b in bits), kind)
        return self._match[key]

    def advantages(self, state: State, goal: State) -> tuple[list[Move], list[float | None]]:
        """The legal moves (in move order) and each one's advantage (None where no classifier matches)."""
        options, values = literal_values(self.literals, self.form, state, goal)
        return options, self.advantages_of(options, values)

    def advantages_of(self, options: tuple[Move, ...], values: np.ndarray) -> list[float | None]:
        """Each move's advantage from its literals' values (moves, literals); None where no classifier matches."""
        found = [self.classifier_for(bits, move.kind) for move, bits in zip(options, values, strict=True)]
        return [None if c is None else c.advantage for c in found]

    def ranked(self, state: State, goal: State) -> list[Move]:
        """The legal moves some classifier matches, by least advantage.

        Ties: the moves whose ``tie`` literal holds first (when the policy has one), then move order.
        """
        options, advantages = self.advantages(state, goal)
        tied = self._tie_values(state, goal, options, advantages)
        scored = [(a, -t, at, move) for at, (move, a, t) in enumerate(zip(options, advantages, tied, strict=True))
                  if a is not None]
        return [move for *_, move in sorted(scored, key=lambda r: r[:3])]

    def _tie_values(self, state: State, goal: State, options: list[Move] | tuple[Move, ...],
                    advantages: list[float | None]) -> list[int]:
        """The ``tie`` literal's value for each move, evaluated only when two best moves tie (else 0s)."""
        best = [a for a in advantages if a is not None]
        if self.tie is None or len(best) < 2 or sorted(best)[1] != min(best):
            return [0] * len(options)
        return [int(v) for v in literal_values((self.tie,), self.form, state, goal, tuple(options))[1][:, 0]]

    def choose(self, state: State, goal: State) -> Move | None:
        """The move of least advantage (ties: move order), or None when no classifier matches any."""
        ranked = self.ranked(state, goal)
        return ranked[0] if ranked else None

    def act(self, state: State, goal: State) -> Action | None:
        """The next action towards ``goal``: None at the goal or when no classifier matches.

        An action that reaches the goal is taken (one action of lookahead). Holding a block
        after its pick, the put of the move chosen before the pick; otherwise the move of
        least advantage, its pick first.
        """
        if state == goal:
            return None
        last = last_action(state, goal)
        if last is not None:
            return last
        chosen, self._chosen = self._chosen, None
        if state.held is not None and chosen is not None and chosen[:2] == (state, goal):
            return put_action(chosen[2])
        move = self.choose(state, goal)
        if move is None:
            return None
        if state.held is not None:
            return put_action(move)
        action = pick_action(state, move.block)
        self._chosen = (successor(state, action), goal, move)
        return action

    def text(self) -> list[str]:
        """The classifiers' lines."""
        return [c.text() for c in self.classifiers]


def used_literals(classifiers: Iterable[LiftedQClassifier], literals: tuple[Literal, ...]
                  ) -> tuple[list[LiftedQClassifier], tuple[Literal, ...]]:
    """The classifiers with their conditions cut down to the literals some classifier tests, and those literals."""
    classifiers = list(classifiers)
    keep = [j for j in range(len(literals)) if any(c.condition[j] != "#" for c in classifiers)]
    cut = [LiftedQClassifier("".join(c.condition[j] for j in keep) or "#", c.kind, c.advantage, c.error,
                             c.experience) for c in classifiers]
    if not keep:  # a condition needs one character: keep the first literal, untested
        keep = [0]
    return cut, tuple(literals[j] for j in keep)


def dumps_feature_policy(classifiers: Iterable[LiftedQClassifier], literals: tuple[Literal, ...],
                         domain: str, formulation: str, meta: dict, tie: Literal | None = None) -> str:
    """The file's text: the lifted Q-classifier format with the literals as its atoms and the domain's PDDL.

    With ``tie``, the literal that breaks ties between moves of equal advantage (``"tie"``).
    """
    cut, kept = used_literals(classifiers, literals)
    doc = {"format": LIFTED_Q_FORMAT, "version": LIFTED_Q_VERSION, "formulation": formulation, "domain": domain,
           "atoms": [lit.text() for lit in kept], "meta": meta, "classifiers": [c.text() for c in cut]}
    if tie is not None:
        doc["tie"] = tie.text()
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"


def feature_policy_from_doc(doc: dict, source: str) -> FeaturePolicy:
    """The policy of a generated-features file already read as JSON; LiftedPolicyError naming what is wrong."""
    domain, atoms, meta = doc.get("domain"), doc.get("atoms"), doc.get("meta", {})
    if not isinstance(domain, str) or not isinstance(atoms, list) or not isinstance(meta, dict):
        raise LiftedPolicyError(f"{source}: 'domain' must be PDDL text, 'atoms' a list and 'meta' an object")
    if not 0 < len(atoms) <= MAX_LITERALS or not all(isinstance(a, str) for a in atoms):
        raise LiftedPolicyError(f"{source}: 'atoms' must name 1..{MAX_LITERALS} literals")
    tie = doc.get("tie")
    if tie is not None and not isinstance(tie, str):
        raise LiftedPolicyError(f"{source}: 'tie' must be a literal")
    try:
        form = parse_formulation(domain, f"{source} (its domain)", str(doc.get("formulation") or "domain"))
        literals = tuple(parse_literal(a) for a in atoms)
        tied = None if tie is None else parse_literal(tie)
    except (CsqlError, ValueError) as exc:
        raise LiftedPolicyError(f"{source}: {exc}") from None
    label = doc.get("formulation")
    if label in BUILTIN and (label == "4op") != form.hand:
        raise LiftedPolicyError(f"{source}: 'formulation' says {label} but its domain is the "
                                f"{'4-operator (hand)' if form.hand else 'move (no hand)'} formulation")
    known = {(p.name, p.arity) for p in form.predicates} | {(c, None) for c in form.constants}
    for lit in (*literals, *(() if tied is None else (tied,))):
        uses = {(lit.feature, 0)} if lit.slot == "holds" else parsed(lit.feature).uses()
        if uses - known:
            wrong = ", ".join(sorted(f"{name}/{'constant' if k is None else k}" for name, k in uses - known))
            raise LiftedPolicyError(f"{source}: literal {lit.text()!r} reads {wrong}, not in the domain")
    return FeaturePolicy(classifier_lines(doc.get("classifiers"), source, len(literals)), literals, form, domain, meta,
                         tied)


__all__ = ["FeaturePolicy", "dumps_feature_policy", "feature_policy_from_doc", "used_literals"]
