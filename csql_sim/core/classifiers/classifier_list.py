"""The classifier list: R- and Q-classifiers in one list, with the index that matches them.

The paper keeps R-classifiers (domain rules) and Q-classifiers (state-action pairs with a
Q-value) in one list (section 4). :class:`ClassifierList` is that list. Matching a
message never scans every classifier:

* conditions with ``#`` (the R-classifiers) are indexed by position in a
  :class:`PatternIndex`: for each position and character a bitset of the patterns that
  accept it, so matching a message is one AND per position over Python integers;
* fully specified conditions (the Q-classifiers, whose condition is a state message)
  are found by exact lookup in a dict keyed by the condition.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from typing import Generic, TypeVar

from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.classifiers.r_classifier import WILDCARD, RClassifier

Classifier = RClassifier | QClassifier
P = TypeVar("P", bound=RClassifier)


class PatternIndex(Generic[P]):
    """Bitset index over ``#`` patterns: position -> character -> patterns accepting it.

    Args:
        items: the classifiers to index, in the order :meth:`match` returns them.

    """

    def __init__(self, items: Iterable[P] = ()) -> None:
        self.items: tuple[P, ...] = tuple(items)
        width = max((len(c.condition) for c in self.items), default=0)
        self._by_char: list[dict[str, int]] = [{} for _ in range(width)]
        self._wild = [0] * width
        self._lengths: dict[int, int] = {}
        for bit, c in enumerate(self.items):
            flag = 1 << bit
            self._lengths[len(c.condition)] = self._lengths.get(len(c.condition), 0) | flag
            for pos, ch in enumerate(c.condition):
                if ch == WILDCARD:
                    self._wild[pos] |= flag
                else:
                    self._by_char[pos][ch] = self._by_char[pos].get(ch, 0) | flag

    def match(self, message: str) -> tuple[P, ...]:
        """The indexed patterns that accept ``message``, in index order."""
        mask = self._lengths.get(len(message), 0)
        for pos, ch in enumerate(message):
            if not mask:
                break
            mask &= self._by_char[pos].get(ch, 0) | self._wild[pos]
        out = []
        while mask:
            low = mask & -mask
            out.append(self.items[low.bit_length() - 1])
            mask ^= low
        return tuple(out)


class ClassifierList:
    """The classifier list: R- and Q-classifiers in one structure, with an index.

    Iterating yields every classifier in insertion order. :meth:`match` gives every
    classifier accepting a message; :meth:`q_for` and :meth:`cover` the Q-classifiers of a
    state message. What the R-classifiers predict is the business of
    :class:`csql_sim.core.model.world_model.WorldModel`, built from :attr:`r_classifiers`.
    """

    def __init__(self, classifiers: Iterable[Classifier] = ()) -> None:
        self._items: list[Classifier] = []
        self._exact: dict[str, dict[str, QClassifier]] = {}
        self._patterns: PatternIndex[RClassifier] | None = None
        for c in classifiers:
            self.add(c)

    def add(self, classifier: Classifier) -> Classifier:
        """Append a classifier and index it."""
        self._items.append(classifier)
        if isinstance(classifier, QClassifier):
            self._exact.setdefault(classifier.condition, {})[classifier.action] = classifier
        else:
            self._patterns = None
        return classifier

    def __iter__(self) -> Iterator[Classifier]:
        return iter(self._items)

    def __len__(self) -> int:
        return len(self._items)

    @property
    def r_classifiers(self) -> list[RClassifier]:
        """The R-classifiers, in list order."""
        return [c for c in self._items if not isinstance(c, QClassifier)]

    @property
    def q_classifiers(self) -> list[QClassifier]:
        """The Q-classifiers, in list order."""
        return [c for c in self._items if isinstance(c, QClassifier)]

    def match(self, message: str) -> list[Classifier]:
        """Every classifier whose condition accepts ``message``: R-classifiers, then Q."""
        if self._patterns is None:
            self._patterns = PatternIndex(self.r_classifiers)
        out: list[Classifier] = list(self._patterns.match(message))
        out.extend(self._exact.get(message, {}).values())
        return out

    def q_for(self, state_message: str) -> dict[str, QClassifier]:
        """The Q-classifiers for a state message, keyed by action message (may be empty)."""
        return self._exact.get(state_message, {})

    def cover(self, state_message: str, actions: Iterable[str], **fields: float) -> dict[str, QClassifier]:
        """Make sure a Q-classifier exists for each (state, action) pair (Figure 2, step 4).

        Missing ones are created with ``fields`` (e.g. ``q=0.0, born=t``); returns all of them.
        """
        existing = self._exact.get(state_message, {})
        for a in actions:
            if a not in existing:
                self.add(QClassifier(state_message, a, **fields))
                existing = self._exact[state_message]
        return existing
