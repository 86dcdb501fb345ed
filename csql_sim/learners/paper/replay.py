"""Learning from experience alone: replay of the transitions trials experienced (CS-QL, both engines).

The trials of a CS-QL learner record each transition they take: the (state, action)
slot and the goal it was taken for (:class:`Experience`). Replay backs up Q-classifiers
from those records only, with eq. 1-2, and never touches a (state, action) no trial took:

* **experience replay** (``replay_hindsight`` false): each experienced (state, goal,
  action) is backed up again towards its recorded successor;
* **hindsight relabelling** (``replay_hindsight`` true, the default): each experienced
  (state, action) transition is backed up for every goal, as in learning to achieve goals
  (Kaelbling 1993) and hindsight experience replay (Andrychowicz et al. 2017). The
  reward is ``payoff`` when the recorded successor is the goal.

A replay phase makes synchronous passes over the records (every backup of a pass reads
the Q-values the pass started from), in slot order: no order taken from the model's
distances. It stops after a pass whose largest |epsilon| is at most ``replay_tolerance``,
or when the replay backups reach the cap: ``replay_ratio`` backups per experienced step
over the learner's life (the last pass then backs up only the first records in order).
The successor of a transition is the one the trial observed; bootstrapping reads the
successor's Q-classifiers, which covering made when the trial posted it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from csql_sim.core.model.world_model import WorldModel


@dataclass(frozen=True)
class SlotLayout:
    """The legal (state, action) pairs of the R-classifiers as slots ``0 .. size - 1``.

    Attributes:
        lo: ``lo[s] .. lo[s + 1]``: state ``s``'s slots, in the order of its legal actions.
        state: each slot's state.
        action: each slot's world action index.
        nxt: each slot's successor state (the transition a trial observes there).

    """

    lo: np.ndarray
    state: np.ndarray
    action: np.ndarray
    nxt: np.ndarray

    @property
    def size(self) -> int:
        """The number of legal (state, action) pairs."""
        return int(self.lo[-1])

    @classmethod
    def of(cls, model: WorldModel) -> SlotLayout:
        """The layout of a world model's table."""
        legal = model.table.legal
        lo = np.zeros(len(legal) + 1, np.int64)
        lo[1:] = np.cumsum([len(row) for row in legal])
        action = np.fromiter((a for row in legal for a in row), np.int64, count=int(lo[-1]))
        state = np.repeat(np.arange(len(legal)), np.diff(lo))
        return cls(lo, state, action, model.table.next_state[state, action].astype(np.int64))


@dataclass
class ReplayResult:
    """What one replay phase did.

    Attributes:
        q: the Q-values after it, ``[goal row, slot]``.
        err: |epsilon| of each entry's last backup (0 where none).
        touched: the entries backed up at least once.
        backups: the replay backups made.
        passes: the passes begun.

    """

    q: np.ndarray
    err: np.ndarray
    touched: np.ndarray
    backups: int
    passes: int


def replay_mask(seen: np.ndarray, layout: SlotLayout, goals: np.ndarray, hindsight: bool) -> np.ndarray:
    """``[goal row, slot]``: the entries replay may back up (see the module).

    Args:
        seen: ``[goal row, slot]``: the (goal, state, action) a trial took.
        layout: the slots.
        goals: the goal state of each row.
        hindsight: relabel every experienced (state, action) for every goal.
    """
    mask = np.broadcast_to(seen.any(axis=0), seen.shape).copy() if hindsight else seen.copy()
    mask &= layout.state[None, :] != goals[:, None]  # nothing to learn at the goal itself
    return mask


def replay_passes(q: np.ndarray, mask: np.ndarray, layout: SlotLayout, goals: np.ndarray, params,
                  budget: int) -> ReplayResult:
    """Synchronous replay passes over the entries of ``mask`` (see the module).

    Args:
        q: ``[goal row, slot]``: the Q-values now (q0 where no classifier exists yet).
        mask: the entries to back up (:func:`replay_mask`).
        layout: the slots.
        goals: the goal state of each row.
        params: CS-QL parameters (gamma, payoff, replay_eta, replay_tolerance).
        budget: the most backups this phase may make (>= 0).
    """
    q = q.copy()
    err = np.zeros_like(q)
    touched = np.zeros_like(mask)
    flat = np.flatnonzero(mask.reshape(-1))
    rows, slots = np.divmod(flat, q.shape[1])
    at_goal = layout.nxt[slots] == goals[rows]
    backups = passes = 0
    while budget - backups > 0 and len(flat):
        take = min(len(flat), budget - backups)
        r, s = rows[:take], slots[:take]
        best = np.maximum.reduceat(q, layout.lo[:-1], axis=1)  # [goal row, state]
        target = np.where(at_goal[:take], params.payoff, params.gamma * best[r, layout.nxt[s]])
        eps = target - q[r, s]
        q[r, s] += params.replay_eta * eps
        err[r, s] = np.abs(eps)
        touched[r, s] = True
        backups, passes = backups + take, passes + 1
        if take < len(flat) or float(np.abs(eps).max()) <= params.replay_tolerance:
            break
    return ReplayResult(q, err, touched, backups, passes)


def replay_budget(params, experienced_steps: int, done: int) -> int:
    """Backups left under the cap: ``replay_ratio`` per experienced step, less those ``done``."""
    return max(0, int(params.replay_ratio * experienced_steps) - done)


class Experience:
    """The transitions trials took: ``seen[goal row, slot]`` and the experienced steps.

    Args:
        layout: the slots.
        goals: the goal state of each row (every state for the unsharded learners).

    """

    def __init__(self, layout: SlotLayout, goals: np.ndarray) -> None:
        self.layout, self.goals = layout, goals
        self.seen = np.zeros((len(goals), layout.size), bool)
        self.steps = 0
        self.replay_backups = 0

    def pairs(self) -> int:
        """The distinct (state, action) pairs experienced, whatever the goal."""
        return int(self.seen.any(axis=0).sum())

    def report(self) -> dict:
        """``experienced_pairs``, ``legal_pairs``, ``experienced_steps`` and ``replay_backups``."""
        return {"experienced_pairs": self.pairs(), "legal_pairs": self.layout.size,
                "experienced_steps": self.steps, "replay_backups": self.replay_backups}


def replay_reference(learner) -> int:
    """A replay phase of the reference engine (:class:`~csql_sim.learners.paper.cs_ql.CSQL`); the backups made.

    Gathers the Q-values of the processing block's posted match sets into ``[goal, slot]``,
    replays (:func:`replay_passes`), and writes each backed-up entry to its Q-classifier
    (covering the (state, goal) first where no trial posted it, as hindsight needs), with
    |epsilon| and ``last_active`` = now.
    """
    p, exp = learner.params, learner.experience
    budget = replay_budget(p, exp.steps, exp.replay_backups)
    if budget == 0 or not exp.seen.any():
        return 0
    lay, goals = exp.layout, exp.goals
    count = len(goals)
    q = np.full((count, lay.size), p.q0)
    slot_of = {}  # (state, action) -> slot
    for slot, (s, a) in enumerate(zip(lay.state.tolist(), lay.action.tolist(), strict=True)):
        slot_of[(s, a)] = slot
    for (s, g), match_set in learner.posted():
        for c, a in zip(match_set.candidates, match_set.actions, strict=True):
            q[g, slot_of[(s, a)]] = c.q
    result = replay_passes(q, replay_mask(exp.seen, lay, goals, p.replay_hindsight), lay, goals, p, budget)
    rows, slots = np.nonzero(result.touched)
    for g, slot in zip(rows.tolist(), slots.tolist(), strict=True):
        match_set = learner.block.post(learner.message(int(lay.state[slot]), g))
        c = match_set.candidates[match_set.index_of(int(lay.action[slot]))]
        c.q, c.error, c.last_active = float(result.q[g, slot]), float(result.err[g, slot]), learner.t
    exp.replay_backups += result.backups
    return result.backups
