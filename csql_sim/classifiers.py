"""Classifiers and the classifier list: '#' matching, add-delete output, and the index.

The paper keeps R-classifiers (domain rules) and Q-classifiers (state-action pairs with a
Q-value) in one list (section 4). :class:`ClassifierList` is that list. Its
"processing block" (Figure 1) never scans every classifier to match a message:

* conditions with ``#`` (the R-classifiers) are indexed by position: for each position
  and character a bitset of the classifiers that accept it, so matching a message is
  one AND per position over Python integers;
* fully specified conditions (the Q-classifiers, whose condition is a state message)
  are found by exact lookup in a dict keyed by the condition.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass

WILDCARD = "#"
R = "R"
Q = "Q"


@dataclass(slots=True, eq=False)
class Classifier:
    """One rule ``if condition then action``.

    Attributes:
        kind: ``"R"`` (domain knowledge) or ``"Q"`` (a state-action pair).
        condition: a pattern over messages; ``#`` matches any character.
        action: the message posted when active: an action message, or for add-delete
            R-classifiers an output pattern whose ``#`` copies the matched message.
        q: Q-value estimate, Q-hat(x, a) of eq. 1 (Q-classifiers).
        strength: 1 - |epsilon|, eq. 4 (for bucket-brigade learners, the bid strength).
        age: how long the classifier has existed, in units of 10,000 steps (Figure 6's ~3.2
            after 2500 trials); see ``CommonParams.age_unit``.
        error: |epsilon| of eq. 2 at the classifier's last activation.
        last_active: the learner's step counter at the last activation; the paper's
            per-step growth of |epsilon| is applied lazily from it.

    """

    kind: str
    condition: str
    action: str
    q: float = 0.0
    strength: float = 1.0
    age: float = 0.0
    error: float = 0.0
    last_active: int = 0

    def matches(self, message: str) -> bool:
        """Whether ``condition`` accepts ``message`` (``#`` matches anything)."""
        return matches(self.condition, message)

    @property
    def is_specific(self) -> bool:
        """True when the condition has no ``#`` (exact lookup applies)."""
        return WILDCARD not in self.condition


def matches(condition: str, message: str) -> bool:
    """Holland matching: equal length, and every non-``#`` character equal."""
    if len(condition) != len(message):
        return False
    return all(c == WILDCARD or c == m for c, m in zip(condition, message, strict=True))


def apply_output(output: str, message: str) -> str:
    """The add-delete rule's output: ``#`` copies the message's character, others overwrite."""
    return "".join(m if o == WILDCARD else o for o, m in zip(output, message, strict=True))


class _PatternIndex:
    """Bitset index over patterns with ``#``: position -> character -> classifiers."""

    def __init__(self) -> None:
        self.items: list[Classifier] = []
        self._by_char: list[dict[str, int]] = []
        self._wild: list[int] = []
        self._cache: dict[str, tuple[Classifier, ...]] = {}

    def rebuild(self, items: Iterable[Classifier]) -> None:
        self.items = list(items)
        width = max((len(c.condition) for c in self.items), default=0)
        self._by_char = [{} for _ in range(width)]
        self._wild = [0] * width
        self._lengths: dict[int, int] = {}
        for bit, c in enumerate(self.items):
            flag = 1 << bit
            self._lengths[len(c.condition)] = self._lengths.get(len(c.condition), 0) | flag
            for p, ch in enumerate(c.condition):
                if ch == WILDCARD:
                    self._wild[p] |= flag
                else:
                    self._by_char[p][ch] = self._by_char[p].get(ch, 0) | flag
        self._cache.clear()

    def match(self, message: str) -> tuple[Classifier, ...]:
        hit = self._cache.get(message)
        if hit is not None:
            return hit
        mask = self._lengths.get(len(message), 0) if self.items else 0
        for p, ch in enumerate(message):
            if not mask:
                break
            mask &= self._by_char[p].get(ch, 0) | self._wild[p]
        out = []
        while mask:
            low = mask & -mask
            out.append(self.items[low.bit_length() - 1])
            mask ^= low
        result = tuple(out)
        self._cache[message] = result
        return result


class ClassifierList:
    """The classifier list: R- and Q-classifiers in one structure, with an index.

    Iterating yields every classifier in insertion order. Use :meth:`match` for all
    classifiers accepting a message, :meth:`preconditions` for the candidate actions,
    :meth:`predict` for the world model, and :meth:`q_for` / :meth:`cover` for the
    Q-classifiers of a state message.
    """

    def __init__(self, classifiers: Iterable[Classifier] = ()) -> None:
        self._items: list[Classifier] = []
        self._patterns = _PatternIndex()
        self._exact: dict[str, dict[str, Classifier]] = {}
        self._dirty = False
        for c in classifiers:
            self.add(c)

    # -- the list -----------------------------------------------------------------
    def add(self, classifier: Classifier) -> Classifier:
        """Append a classifier and index it."""
        self._items.append(classifier)
        if classifier.is_specific:
            self._exact.setdefault(classifier.condition, {})[classifier.action] = classifier
        else:
            self._dirty = True
        return classifier

    def remove_if(self, predicate) -> int:
        """Remove every classifier for which ``predicate(c)`` is true; return how many."""
        keep = [c for c in self._items if not predicate(c)]
        removed = len(self._items) - len(keep)
        self._items = []
        self._exact.clear()
        self._patterns = _PatternIndex()
        for c in keep:
            self.add(c)
        self._dirty = True
        return removed

    def __iter__(self) -> Iterator[Classifier]:
        return iter(self._items)

    def __len__(self) -> int:
        return len(self._items)

    def of_kind(self, kind: str) -> list[Classifier]:
        """Every classifier of ``kind`` (``"R"`` or ``"Q"``), in list order."""
        return [c for c in self._items if c.kind == kind]

    # -- matching -----------------------------------------------------------------
    def _pattern_index(self) -> _PatternIndex:
        if self._dirty:
            self._patterns.rebuild(c for c in self._items if not c.is_specific)
            self._dirty = False
        return self._patterns

    def match(self, message: str) -> list[Classifier]:
        """Every classifier whose condition accepts ``message``."""
        out = list(self._pattern_index().match(message))
        out.extend(self._exact.get(message, {}).values())
        return out

    def preconditions(self, state_message: str) -> tuple[Classifier, ...]:
        """The precondition R-classifiers satisfied by a state message (Figure 2, step 3).

        Their actions are the candidate action messages.
        """
        return tuple(
            c for c in self._pattern_index().match(state_message) if c.kind == R and c.action[0] == "A"
        )

    def predict(self, message: str) -> str:
        """The world model: apply the add-delete R-classifier that the message activates.

        Args:
            message: a state message whose action slot holds the action just taken.

        Raises:
            KeyError: when no add-delete rule (or more than one) matches.

        """
        rules = [c for c in self._pattern_index().match(message) if c.kind == R and c.action[0] == "S"]
        if len(rules) != 1:
            raise KeyError(f"{len(rules)} add-delete rules match {message!r}")
        return apply_output(rules[0].action, message)

    def q_for(self, state_message: str) -> dict[str, Classifier]:
        """The Q-classifiers for a state message, keyed by action message (may be empty)."""
        return self._exact.get(state_message, {})

    def cover(self, state_message: str, actions: Iterable[str], **fields: float) -> dict[str, Classifier]:
        """Make sure a Q-classifier exists for each (state, action) pair (Figure 2, step 4).

        Missing ones are created with ``fields`` (e.g. ``q=0.0``); returns all of them.
        """
        existing = self._exact.get(state_message, {})
        for a in actions:
            if a not in existing:
                self.add(Classifier(Q, state_message, a, **fields))
                existing = self._exact[state_message]
        return existing
