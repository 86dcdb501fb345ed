"""Lifted Q-classifiers: a condition over the features of a move, the move's kind, a learned advantage.

A lifted Q-classifier reads one character per feature of a move (``1`` holds, ``0`` does not,
``#`` either), whatever those features are: the given atoms
(:mod:`csql_sim.core.policies.lifted_policy`) or generated literals
(:mod:`csql_sim.core.policies.feature_policy`). It is written::

    Q 1110#1### move(?x,?d)->table  advantage=0.007 error=0.015 experience=4743

with the action (move ``?x`` to the table, ``->table``, or onto a block ``?d``, ``->block``),
the learned **advantage** (moves more than the state's best move the classifier expects its
move to cost), the mean absolute error of that prediction and its experience (updates).
This module is the line, its reading and matching; it knows no feature's meaning.
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable
from dataclasses import dataclass

from csql_sim.core.state.moves import KINDS
from csql_sim.infra import formats
from csql_sim.infra.errors import CsqlError

LIFTED_Q_FORMAT = formats.LIFTED_Q
LIFTED_Q_VERSION = 1
MAX_CLASSIFIERS = 4096
MAX_EXPERIENCE_DIGITS = 18
"""A classifier's experience (updates) fits in 18 digits; longer is a corrupt or hostile file."""
_NUM = r"(-?\d+(?:\.\d+)?)"
_LINE = re.compile(r"Q ([01#]+) move\(\?x,\?d\)->(table|block)\s+advantage=" + _NUM +
            r"\s+error=(\d+(?:\.\d+)?)\s+experience=(\d+)")


class LiftedPolicyError(CsqlError):
    """A lifted Q-classifier file or line that does not follow the documented form."""


def condition_holds(condition: str, bits: tuple[int, ...]) -> bool:
    """Whether a condition (``1``, ``0``, ``#`` per atom) holds for a move's relations."""
    return all(c == "#" or int(c) == b for c, b in zip(condition, bits, strict=True))


@dataclass(frozen=True)
class LiftedQClassifier:
    """One lifted Q-classifier (see the module docstring)."""

    condition: str
    kind: str
    advantage: float = 0.0
    error: float = 0.0
    experience: int = 0

    def __post_init__(self) -> None:
        if not self.condition or set(self.condition) - set("01#"):
            raise LiftedPolicyError(f"condition {self.condition!r}: expected characters 0, 1, # (one per atom)")
        if self.kind not in KINDS:
            raise LiftedPolicyError(f"move kind {self.kind!r}: expected one of {', '.join(KINDS)}")

    def matches(self, bits: tuple[int, ...], kind: str) -> bool:
        """Whether the condition holds for a move with relations ``bits`` of kind ``kind``."""
        return kind == self.kind and condition_holds(self.condition, bits)

    @property
    def generality(self) -> int:
        """The number of ``#`` in the condition."""
        return self.condition.count("#")

    def text(self) -> str:
        """The classifier's line."""
        return (f"Q {self.condition} move(?x,?d)->{self.kind}  advantage={self.advantage:.3f} "
                f"error={self.error:.3f} experience={self.experience}")

    def words(self, atoms: tuple[str, ...]) -> str:
        """The condition in words: the atoms that must hold (and, with ``not``, must not)."""
        parts = [atom if c == "1" else f"not {atom}" for atom, c in zip(atoms, self.condition, strict=True) if c != "#"]
        return f"move ?x to {'the table' if self.kind == 'table' else 'block ?d'} if {' and '.join(parts) or 'always'}"


def parse_lifted_q(line: str) -> LiftedQClassifier:
    """Read one classifier line (:meth:`LiftedQClassifier.text`)."""
    found = _LINE.fullmatch(line.strip())
    if not found:
        raise LiftedPolicyError(f"lifted Q-classifier {line[:80]!r}: expected 'Q <condition> move(?x,?d)->table|block "
                                "advantage=A error=R experience=N'")
    cond, kind, advantage, error, experience = found.groups()
    if len(experience) > MAX_EXPERIENCE_DIGITS:
        raise LiftedPolicyError(f"lifted Q-classifier {line[:80]!r}: experience has {len(experience):,} digits "
                                f"(at most {MAX_EXPERIENCE_DIGITS})")
    numbers = float(advantage), float(error)
    if not all(math.isfinite(x) for x in numbers):
        raise LiftedPolicyError(f"lifted Q-classifier {line[:80]!r}: advantage and error must be finite numbers")
    return LiftedQClassifier(cond, kind, *numbers, int(experience))


def most_specific(classifiers: Iterable[LiftedQClassifier], bits: tuple[int, ...], kind: str
                  ) -> LiftedQClassifier | None:
    """The matching classifier with the fewest ``#`` (ties: the smaller error, then list order)."""
    best = None
    for c in classifiers:
        if c.matches(bits, kind) and (best is None or (c.generality, c.error) < (best.generality, best.error)):
            best = c
    return best


def classifier_lines(lines: object, source: str, width: int, pad: str = "") -> list[LiftedQClassifier]:
    """The classifiers of a file's ``classifiers`` list, each condition ``width`` atoms long."""
    if not isinstance(lines, list) or not all(isinstance(x, str) for x in lines):
        raise LiftedPolicyError(f"{source}: 'classifiers' must be a list of lines")
    if not 0 < len(lines) <= MAX_CLASSIFIERS:
        raise LiftedPolicyError(f"{source} holds {len(lines)} classifiers; expected 1..{MAX_CLASSIFIERS}")
    try:
        out = [_padded(parse_lifted_q, x, pad) for x in lines]
    except LiftedPolicyError as exc:
        raise LiftedPolicyError(f"{source}: {exc}") from None
    wrong = next((c for c in out if len(c.condition) != width), None)
    if wrong is not None:
        raise LiftedPolicyError(f"{source}: condition {wrong.condition!r} has {len(wrong.condition)} atoms, "
                                f"the file names {width}")
    return out


def _padded(parse, line: str, pad: str) -> LiftedQClassifier:
    """One line read with ``pad`` (``#`` for atoms the file predates) after its condition."""
    if pad:
        head, sep, rest = line.strip().partition(" move(")
        line = head + pad + sep + rest
    return parse(line)




__all__ = ["LIFTED_Q_FORMAT", "LIFTED_Q_VERSION", "MAX_CLASSIFIERS", "LiftedPolicyError", "LiftedQClassifier",
           "classifier_lines", "condition_holds", "most_specific", "parse_lifted_q"]
