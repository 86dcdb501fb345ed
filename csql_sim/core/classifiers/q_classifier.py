"""Q-classifiers: state-action pairs with a Q-value, made on demand (paper section 4).

A Q-classifier's condition is a full state message (no ``#``) and its action an action
message. The processing block creates one for each legal action of a posted message the
first time it is seen (Figure 2, step 4: cover).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar


@dataclass(slots=True, eq=False)
class QClassifier:
    """One ``if state message then action message`` pair with its learned estimates.

    Attributes:
        condition: the state message (action slot ``0``).
        action: the action message.
        q: Q-value estimate, Q-hat(x, a) of eq. 1.
        strength: 1 - |epsilon|, eq. 4 (for bucket-brigade learners, the bid strength).
        age: how long the classifier has existed, in units of ``CommonParams.age_unit``
            steps (Figure 6's ~3.2 after 2500 trials).
        error: |epsilon| of eq. 2 at the classifier's last activation.
        last_active: the learner's step counter at the last activation; the paper's
            per-step growth of |epsilon| is applied lazily from it.
        born: the learner's step counter when the classifier was created (its age is
            measured from it).

    """

    condition: str
    action: str
    q: float = 0.0
    strength: float = 1.0
    age: float = 0.0
    error: float = 0.0
    last_active: int = 0
    born: int = 0
    kind: ClassVar[str] = "Q"
