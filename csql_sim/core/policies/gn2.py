"""GN2, the best hand-written near-linear-time planner for the blocks world: a yardstick, not a learner.

Slaney and Thiébaux, "Blocks World revisited", Artificial Intelligence 125 (2001) 119-153,
describe the near-optimal planners of the domain in terms of **constructive moves** (a
misplaced block moved to its goal place, which is ready: the table, or a clear block in its
goal position) and **deadlocks** (Gupta and Nau 1992: misplaced blocks each of which must
leave its place before another can make its final move; at least one block of every
deadlock goes to the table first, and the set of table visitors is a hitting set of the
deadlocks):

* **GN1** (:class:`csql_sim.core.policies.gn1.Gn1Policy`): make a constructive move while there
  is one; otherwise move a clear deadlocked block to the table;
* **GN2** (this module) is GN1 with a better choice in the non-constructive case, among the
  clear deadlocked blocks (ties: block order). The paper's text was not at hand (only its
  definitions), so this choice was read in several ways (:data:`READINGS`), each written
  from the description, not from the authors' code:

  - ``enables``: one whose move to the table makes a constructive move possible at once
    (O(1): only the block c under it changes; c is misplaced with its goal place ready, or
    c is in position and the block that goes on c is clear and misplaced);
  - ``longest-run``: one after whose move the most constructive moves follow
    (:func:`constructive_run`, O(1 + the run));
  - ``fewest-stuck``: one that leaves the fewest deadlocked blocks (the tracker's counts);
  - ``hitting-set``: one in a greedy hitting set of the deadlocks (the tracker's ``cover``,
    :func:`~csql_sim.core.state.deadlock_kernel.deadlock_cover`: every deadlocked block a
    visitor, dropped lowest in its tower first unless that leaves a deadlock), ties to
    ``longest-run`` (this is the hand ordering's choice);
  - ``enables-then-hitting-set`` (**adopted**, :data:`READING`): ``enables``, ties to
    ``hitting-set``.

  When no clear block is deadlocked, GN1's fallbacks: a block whose move enables a
  constructive one, one above a block needed next, any (guards only).

**Calibration** (tuning tasks only, :mod:`csql_sim.core.model.task_split`; ``python
benchmarks/gn2_readings.py``, 2026-12-02): plan length / proven optimum on the first 10
tall-tower tasks per n (seed 0) and on the first 100 benchmark pairs at n = 20, and GN2 / GN1
on 30 tall towers per n (seed 0), against the figures of the authors' C code (10 tall towers
per n; random problems at n = 20)::

                              tall: / optimum        tall: / GN1            pairs: / optimum
    reading                   25     50     100      25     50     100      20
    GN1                       1.028  1.112  1.118    1      1      1        1.038
    enables                   1.023  1.089  1.112    0.992  0.993  0.985    1.034
    longest-run               1.023  1.087  1.112    0.992  0.992  0.984    1.032
    fewest-stuck              1.026  1.089  1.098    0.990  0.986  0.982    1.025
    hitting-set               1.000  1.006  1.024    0.960  0.943  0.911    1.005
    enables-then-hitting-set  1.000  1.020  1.028    0.964  0.946  0.920    1.009
    authors' GN1              1.037  1.058  1.127    -      -      -        -
    authors' GN2              1.000  1.021  1.060    0.964  0.965  0.941    1.009

The adopted reading agrees with the authors' GN2 within 0.021 on every figure but GN2 /
optimum at n = 100 (1.028 against 1.060; our GN1 there is within 0.01 of theirs, at n = 50
0.054 off: 10 towers are a small sample). The one-move readings without the hitting set
save only 0.7-1.8% over GN1 where the authors' GN2 saves 3.5-6%. Combinations measured too
and not kept: ``longest-run`` then ``fewest-stuck``, and the reverse, within 0.004 of
``fewest-stuck``; ``longest-run`` then the hitting set, 1.000 / 1.019 / 1.027 / 1.009 (as close
as the adopted reading, which keeps the one-move test of the first); the hitting set alone,
as ``hitting-set``. GN2 is still sometimes longer than GN1 on random pairs (about 1 pair in
100 at n = 10, 4 in 100 at n = 20; tests/core/policies/test_gn2.py).

In the paper's four operators a move is a pick and the put that follows, as in GN1: holding
a block, :class:`Gn2Policy` puts it on its goal place if that is ready, else on the table;
a goal that holds a block is reached through :func:`~csql_sim.core.state.move_relations.towards`.
The relations (well placed, clear, deadlocked, the hitting set) are kept up to date move by
move by :class:`~csql_sim.core.state.relation_tracker.RelationTracker` (compiled passes over
the deadlock graph, the hitting set only in states without a constructive move where two
enabling candidates tie), so a plan of a 1,000-block tower takes seconds.
"""

from __future__ import annotations

from collections.abc import Callable

from csql_sim.core.policies.contract import Policy
from csql_sim.core.state.move_relations import towards
from csql_sim.core.state.moves import Move, pick_action
from csql_sim.core.state.relation_tracker import KeptRelations, RelationTracker
from csql_sim.core.state.world import TABLE, Action, ActionKind, State


def constructive(tracker: RelationTracker, b: int) -> bool:
    """Whether block b is misplaced, clear and its goal place is ready (a move of b to it is constructive)."""
    if tracker.placed[b] or b not in tracker.clear:
        return False
    d = tracker.goal[b]
    return d == TABLE or (d >= 0 and d != b and tracker.placed[d] and d in tracker.clear)


def enables_constructive(tracker: RelationTracker, b: int) -> bool:
    """Whether moving clear block b (not on the table) to the table makes a constructive move possible.

    Only the block c under b changes (it becomes clear): a constructive move of c, or onto c.
    """
    c = tracker.sup[b]
    if c < 0:
        return False
    if not tracker.placed[c]:
        d = tracker.goal[c]
        return d == TABLE or (d >= 0 and d != b and tracker.placed[d] and d in tracker.clear)
    x = tracker.goal_above[c]
    return x is not None and x != b and not tracker.placed[x] and x in tracker.clear


def constructive_run(tracker: RelationTracker, b: int) -> int:
    """How many constructive moves follow one another once clear block b (not on the table) goes to the table.

    A constructive move never disables another (each goal place has one goal block), so the
    count does not depend on their order. Only the blocks the moves touch are looked at
    (a small overlay on the tracker's arrays), so it costs O(1 + the count).
    """
    goal, goal_above = tracker.goal, tracker.goal_above
    sup, above, placed = {b: TABLE}, {tracker.sup[b]: None}, {b: goal[b] == TABLE}

    def is_placed(x: int) -> bool:
        return placed.get(x, tracker.placed[x])

    def is_clear(x: int) -> bool:
        return above.get(x, tracker.above[x]) is None

    def ready(x: int) -> bool:
        d = goal[x]
        return not is_placed(x) and is_clear(x) and (d == TABLE or (d >= 0 and is_placed(d) and is_clear(d)))

    work, count = [tracker.sup[b], b], 0
    while work:
        y = work.pop()
        x = goal_above[y] if is_placed(y) else y
        if x is None or not ready(x):
            continue
        s, d = sup.get(x, tracker.sup[x]), goal[x]
        if s >= 0:
            above[s] = None
            work.append(s)
        sup[x], placed[x] = d, True
        if d >= 0:
            above[d] = x
        count += 1
        work.append(x)
    return count


def enables(tracker: RelationTracker, b: int) -> int:
    """1 when moving b to the table makes a constructive move possible at once (:func:`enables_constructive`)."""
    return int(enables_constructive(tracker, b))


def fewer_stuck(tracker: RelationTracker, b: int) -> int:
    """Minus the number of deadlocked blocks once b is on the table (more is better)."""
    return -tracker.stuck_after[Move(b, TABLE)]


def in_hitting_set(tracker: RelationTracker, b: int) -> int:
    """1 when b is in the greedy hitting set of the deadlocks (the tracker's ``cover``)."""
    return int(b in tracker.cover)


Criterion = Callable[[RelationTracker, int], int]

READINGS: dict[str, tuple[Criterion, ...]] = {
    "enables": (enables,),
    "longest-run": (constructive_run,),
    "fewest-stuck": (fewer_stuck,),
    "hitting-set": (in_hitting_set, constructive_run),
    "enables-then-hitting-set": (enables, in_hitting_set),
}
"""The readings of GN2's non-constructive choice (module docstring): criteria, each maximised in turn."""
READING = "enables-then-hitting-set"
"""The reading ``gn2`` is: the one that agrees with the authors' figures (module docstring)."""


def best(tracker: RelationTracker, candidates: list[int], criteria: tuple[Criterion, ...]) -> int:
    """The first candidate (block order) among those best by each criterion in turn.

    A criterion is computed only while more than one candidate is left.
    """
    for criterion in criteria:
        if len(candidates) == 1:
            break
        scores = [criterion(tracker, b) for b in candidates]
        top = max(scores)
        candidates = [b for b, v in zip(candidates, scores, strict=True) if v == top]
    return candidates[0]


def gn2_block(tracker: RelationTracker, reading: str = READING) -> int | None:
    """The block GN2 moves next in a hand-empty state (module docstring), or None if none is misplaced."""
    clear = sorted(tracker.clear)
    for b in clear:
        if constructive(tracker, b):
            return b
    stuck = tracker.stuck
    movable = [b for b in clear if not tracker.placed[b] and tracker.sup[b] != TABLE]
    candidates = [b for b in movable if b in stuck]
    if candidates:
        return best(tracker, candidates, READINGS[reading])
    for wanted in (lambda b: enables_constructive(tracker, b), tracker.above_needed, lambda b: True):
        for b in movable:
            if wanted(b):
                return b
    return None


class Gn2Policy(Policy):
    """The GN2 rules as a policy (named baseline ``gn2``; see the module docstring)."""

    name = "gn2"
    blocks: int | None = None

    def __init__(self, reading: str = READING) -> None:
        if reading not in READINGS:
            raise ValueError(f"unknown GN2 reading {reading!r}; expected one of {', '.join(READINGS)}")
        self._kept = KeptRelations()
        self.reading = reading

    def act(self, state: State, goal: State) -> Action | None:
        """The next action towards ``goal``, or None at the goal."""
        target, last = towards(state, goal)
        if target is None:
            return last
        tracker = self._kept.of(state, target)
        held = state.held
        if held is not None:
            d = target.support[held]
            ready = d != TABLE and tracker.placed[d] and d in tracker.clear
            action = Action(ActionKind.STACK, held, d) if ready else Action(ActionKind.PUTDOWN, held)
        else:
            b = gn2_block(tracker, self.reading)
            action = None if b is None else pick_action(state, b)
        self._kept.chose(action)
        return action
