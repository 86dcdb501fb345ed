"""The processing block (paper Figure 1): post a message, match, cover.

When a state message is posted, the block

1. *matches* it against the classifier list: the precondition R-classifiers that accept
   it name the candidate actions (Figure 2, step 3), found through the world model's
   index, never by scanning the list;
2. *covers* it: makes sure a Q-classifier exists for each (state, candidate) pair,
   creating the missing ones (Figure 2, step 4).

The result is the message's :class:`MatchSet`. The block memoizes match sets per
message, since the retrieval for a message never changes while nothing is removed: the
same classifier objects are found each time.
"""

from __future__ import annotations

from collections.abc import Callable

from csql_sim.core.classifiers.classifier_list import ClassifierList
from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.model.world_model import WorldModel
from csql_sim.core.state.message import decode_code, layout


class MatchSet:
    """The Q-classifiers of one posted state message, one per candidate action.

    Attributes:
        message: the state message (action slot ``0``).
        candidates: the candidates' Q-classifiers, in precondition-rule order.
        actions: the world's action index of each candidate (action code minus one).

    """

    __slots__ = ("message", "candidates", "actions")

    def __init__(self, message: str, candidates: tuple[QClassifier, ...], actions: tuple[int, ...]) -> None:
        self.message = message
        self.candidates = candidates
        self.actions = actions

    def index_of(self, action: int) -> int:
        """The candidate position of a world action index.

        Raises:
            ValueError: when the action is not a candidate of this message.
        """
        return self.actions.index(action)


class ProcessingBlock:
    """Posts state messages to a classifier list and returns their match sets.

    Args:
        classifiers: the classifier list Q-classifiers are created in.
        world_model: the R-classifiers' world model (its precondition rules match).
        new_fields: the field values of a freshly created Q-classifier (called at each
            cover, so it may read the learner's clock).

    """

    def __init__(self, classifiers: ClassifierList, world_model: WorldModel,
                 new_fields: Callable[[], dict]) -> None:
        self.classifiers = classifiers
        self.world_model = world_model
        self.new_fields = new_fields
        self._width = layout(world_model.n).action_width
        self._sets: dict[str, MatchSet] = {}

    def post(self, message: str) -> MatchSet:
        """The match set of a state message: match, then cover (memoized)."""
        match_set = self._sets.get(message)
        if match_set is None:
            actions = self.world_model.legal_actions(message)
            found = self.classifiers.cover(message, actions, **self.new_fields())
            w = self._width
            match_set = MatchSet(message, tuple(found[a] for a in actions),
                                 tuple(decode_code(a[1 : 1 + w]) - 1 for a in actions))
            self._sets[message] = match_set
        return match_set

    def posted(self) -> list[tuple[str, MatchSet]]:
        """Every message posted so far with its match set, in the order first posted."""
        return list(self._sets.items())
