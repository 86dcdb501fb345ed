"""The relations of :class:`~csql_sim.core.state.move_relations.MoveRelations`, kept up to date move by move.

:class:`MoveRelations` computes every relation of one state from scratch: all O(n^2) moves
and, for each move to the table, the deadlock graph again. :class:`RelationTracker` holds
one mutable state towards one fixed target and updates only what an action changes:

* the supports, the block above each block, the clear blocks and the well-placed flags
  (a pick or a put changes the flag of the moved block alone: nothing stands on it);
* the deadlock graph is read from these arrays (each misplaced block has at most three
  out-edges: the block on it, the block on its goal support, its misplaced goal support),
  and its cycles are found once per state;
* ``least-stuck`` needs the deadlocked count after each move to the table
  (:func:`~csql_sim.core.state.deadlock_kernel.deadlock_counts`: only a deadlocked block's
  move changes it, and only its own strongly connected component is searched again).
  These counts are computed when asked for (:meth:`RelationTracker.resolve`), so a
  caller that does not need ``least-stuck`` in a state does not pay for it.
* ``cover`` (:func:`~csql_sim.core.state.deadlock_kernel.deadlock_cover`) is computed at the
  same time, and only when some block is deadlocked: outside the cover's blocks it is 0.

The compiled kernels (:mod:`~csql_sim.core.state.deadlock_kernel`, numba) are imported when a
tracker first needs them, and run again only when what they read changed (a put on the table
after its pick leaves the graph and its cover as they were). The relations are exact, the same
as from scratch (tested move by move).
:meth:`RelationTracker.candidates` gives, in move order, the first move of every class of
moves with the same block, kind and relations: a greedy choice of least advantage with
ties to the first move in order is the same over the candidates as over all moves.
"""

from __future__ import annotations

import numpy as np

from csql_sim.core.state.moves import Move, legal_moves
from csql_sim.core.state.state import State
from csql_sim.core.state.world import HAND, TABLE, Action, ActionKind, WorldError

Bits = tuple[int, ...]


class RelationTracker:
    """One state's move relations towards a fixed hand-empty target, updated by :meth:`apply`."""

    def __init__(self, state: State, target: State) -> None:
        if state.n != target.n:
            raise WorldError(f"state has {state.n} blocks but target has {target.n}")
        if target.held is not None:
            raise WorldError("the target of the move relations holds no block")
        n = state.n
        self.n = n
        self.sup = list(state.support)
        self.goal = target.support
        self.goal_above: list[int | None] = list(target.above_of)
        self.above: list[int | None] = list(state.above_of)
        self.held = state.held
        self.placed = self._initial_placed()
        self.clear = {b for b in range(n) if self.is_clear(b)}
        self._goal_a = np.array(target.support, np.int64)
        self._goal_above_a = np.array([-1 if a is None else a for a in self.goal_above], np.int64)
        self._sup_a = np.array(self.sup, np.int64)
        self._above_a = np.array([-1 if a is None else a for a in self.above], np.int64)
        self._placed_a = np.array(self.placed, np.bool_)
        self._fresh = False
        self._classes: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None  # class_arrays, cover unknown
        self._graph_key: tuple[bytes, bytes] | None = None  # the deadlock graph last searched (above, placed)
        self._graph_cover: tuple[bytes, frozenset[int]] | None = None  # its cover, with the supports it read

    def _initial_placed(self) -> list[bool]:
        """Each block's well-placed flag: on its goal support, with everything below it well placed."""
        known: list[bool | None] = [None] * self.n
        for b in range(self.n):
            chain, c = [], b
            while known[c] is None:
                s = self.sup[c]
                if s != self.goal[c] or s < 0:
                    known[c] = s == self.goal[c]
                    break
                chain.append(c)
                c = s
            for d in chain:
                known[d] = known[c]
        return [bool(k) for k in known]

    @property
    def support(self) -> tuple[int, ...]:
        """The current state's supports."""
        return tuple(self.sup)

    def state(self) -> State:
        """The current state."""
        return State(self.support)

    def is_clear(self, b: int) -> bool:
        """Nothing on block b and it is not held."""
        return self.above[b] is None and self.sup[b] != HAND

    # ---------------------------------------------------------------- actions

    def apply(self, action: Action) -> None:
        """Apply a legal action (raises WorldError otherwise)."""
        x, kind = action.block, action.kind
        if kind in (ActionKind.PICKUP, ActionKind.UNSTACK):
            s = TABLE if kind is ActionKind.PICKUP else action.target
            if self.held is not None or x not in self.clear or self.sup[x] != s:
                raise WorldError(f"{kind.value} of block {x} is not legal here")
            if s >= 0:
                self.above[s] = None
                self._above_a[s] = -1
                self.clear.add(s)
            self.clear.discard(x)
            self.sup[x], self.held, self.placed[x] = HAND, x, False
        else:
            s = TABLE if kind is ActionKind.PUTDOWN else action.target
            if self.held != x or (s >= 0 and s not in self.clear):
                raise WorldError(f"{kind.value} of block {x} is not legal here")
            self.sup[x], self.held = s, None
            if s >= 0:
                self.above[s] = x
                self._above_a[s] = x
                self.clear.discard(s)
            self.clear.add(x)
            self.placed[x] = self.goal[x] == s and (s < 0 or self.placed[s])
        self._sup_a[x] = self.sup[x]
        self._placed_a[x] = self.placed[x]
        self._fresh = False
        self._classes = None

    # ---------------------------------------------------------------- the deadlock graph

    def _graph_placed(self) -> np.ndarray:
        """The well-placed flags of the deadlock graph: a held block counts as standing on the table."""
        if self.held is None:
            return self._placed_a
        placed = self._placed_a.copy()
        placed[self.held] = self.goal[self.held] == TABLE
        return placed

    def _refresh(self) -> None:
        """The deadlocked blocks; the table moves' counts wait for :meth:`resolve`."""
        if self._fresh:
            return
        placed = self._graph_placed()
        key = (self._above_a.tobytes(), placed.tobytes())
        if key != self._graph_key:  # else the graph is the last one's (a put on the table after its pick)
            from csql_sim.core.state.deadlock_kernel import deadlocked  # numba: imported by a planner that needs it

            mask = np.zeros(self.n, np.bool_)
            deadlocked(self._above_a, self._goal_a, placed, mask)
            self._graph_key, self._stuck_mask = key, mask
            self._stuck = frozenset(np.flatnonzero(mask).tolist())
            self._graph_cover = None
        self._movers = self._table_movers()
        self._stuck_after: dict[Move, int] | None = None
        self._cover: frozenset[int] | None = None if self._stuck else frozenset()
        if not any(x in self._stuck for x in self._movers):  # no move changes the count, no mover is in the cover
            self._stuck_after = {Move(x, TABLE): len(self._stuck) for x in self._movers}
            self._cover = frozenset()
        self._fresh = True

    def resolve(self) -> None:
        """Count the deadlocked blocks after every move to the table (``least-stuck``); find the ``cover``."""
        self.resolve_cover()
        if self._stuck_after is None:
            from csql_sim.core.state.deadlock_kernel import deadlock_counts

            mask = np.zeros(self.n, np.bool_)
            counts = deadlock_counts(self._sup_a, self._above_a, self._goal_a, self._graph_placed(),
                                     np.array(self._movers, np.int64), mask)
            self._stuck_after = {Move(x, TABLE): c for x, c in zip(self._movers, counts.tolist(), strict=True)}

    def resolve_cover(self) -> None:
        """Find the ``cover`` (the counts of ``least-stuck`` may stay unknown)."""
        self._refresh()
        if self._cover is None:
            support = self._sup_a.copy()
            if self.held is not None:
                support[self.held] = TABLE
            key = support.tobytes()
            if self._graph_cover is None or self._graph_cover[0] != key:  # else the same graph and supports
                from csql_sim.core.state.deadlock_kernel import deadlock_cover

                cover = np.zeros(self.n, np.bool_)
                deadlock_cover(support, self._above_a, self._goal_a, self._graph_placed(), self._stuck_mask, cover)
                self._graph_cover = (key, frozenset(np.flatnonzero(cover).tolist()))
            self._cover = self._graph_cover[1]

    @property
    def stuck(self) -> frozenset[int]:
        """The deadlocked blocks (a held block counts as standing on the table)."""
        self._refresh()
        return self._stuck

    @property
    def cover(self) -> frozenset[int]:
        """The ``cover`` blocks: a greedy hitting set of the deadlocks (:meth:`resolve_cover`)."""
        self.resolve_cover()
        return self._cover

    @property
    def stuck_after(self) -> dict[Move, int]:
        """The number of deadlocked blocks after each move to the table."""
        self.resolve()
        return self._stuck_after

    @property
    def least(self) -> int:
        """The fewest deadlocked blocks any move to the table leaves (0 when there is none)."""
        return min(self._stuck_after.values(), default=0)

    def _table_movers(self) -> list[int]:
        if self.held is not None:
            return [self.held]
        return sorted(x for x in self.clear if self.sup[x] != TABLE)

    # ---------------------------------------------------------------- the relations of moves

    def moves(self) -> tuple[Move, ...]:
        """The legal moves, in the order of :func:`~csql_sim.core.state.moves.moves`."""
        return legal_moves(self.held, sorted(self.clear), self.sup)

    def _ready(self, d: int, mover: int) -> bool:
        return d == TABLE or (d >= 0 and d != mover and self.placed[d] and d in self.clear)

    def above_needed(self, x: int) -> bool:
        """A block under x is misplaced with its goal place ready, or the placed goal support of a misplaced one."""
        placed, goal_above, goal, sup = self.placed, self.goal_above, self.goal, self.sup
        below = sup[x]
        while below >= 0:
            if placed[below]:
                owner = goal_above[below]
                if owner is not None and not placed[owner]:
                    return True
            elif self._ready(goal[below], below):
                return True
            below = sup[below]
        return False

    def bits(self, move: Move) -> Bits:
        """The move's relations, as :meth:`MoveRelations.bits` gives them."""
        self.resolve()
        x, d = move.block, move.onto
        return (int(not self.placed[x]), int(self.goal[x] == d), int(self._ready(d, x)), int(x in self._stuck),
                int(self.above_needed(x)), int(d == TABLE and self._stuck_after[move] == self.least),
                int(bool(self._stuck)), int(self.held is not None), int(x in self._cover))

    def candidates(self, resolve: bool = True) -> list[tuple[Move, Bits]]:
        """The first move of every (block, kind, relations) class, in move order (module docstring).

        With ``resolve`` False, ``least-stuck`` and ``cover`` are -1 (unknown) where they were not yet
        found (:meth:`resolve`, :meth:`resolve_cover`).
        """
        return [(Move(x, d), bits) for x, d, bits in self.classes(resolve)]

    def classes(self, resolve: bool = True) -> list[tuple[int, int, Bits]]:
        """:meth:`candidates` as (block, destination, relations), without building the moves.

        Onto blocks, a move's relations differ only by ``goal-on`` and ``ready``: the goal support
        (when clear), the first well-placed clear block and the first misplaced one stand for all.
        """
        self._refresh()
        if resolve:
            self.resolve()
        after = self._stuck_after
        fewest_of = None if after is None else {m.block: int(c == self.least) for m, c in after.items()}
        placed, goal, sup, stuck_set, cover_set, clear_set = \
            self.placed, self.goal, self.sup, self._stuck, self._cover, self.clear
        clear = sorted(clear_set)
        good = [b for b in clear if placed[b]][:3]  # the first not x, its support or its goal is among three
        bad = [b for b in clear if not placed[b]][:3]
        deadlock, holding = int(bool(stuck_set)), int(self.held is not None)
        out = []
        for x in ([self.held] if self.held is not None else clear):
            mis, stuck, needed = int(not placed[x]), int(x in stuck_set), int(self.above_needed(x))
            cover = 0 if not stuck else -1 if cover_set is None else int(x in cover_set)
            g, s = goal[x], sup[x]
            if s != TABLE:
                fewest = -1 if fewest_of is None else fewest_of[x]
                out.append((x, TABLE, (mis, int(g == TABLE), 1, stuck, needed, fewest, deadlock, holding, cover)))
            found = {}  # destination: ready
            if g >= 0 and g != x and g != s and g in clear_set:
                found[g] = int(placed[g])
            for group, ready in ((good, 1), (bad, 0)):
                for y in group:
                    if y != x and y != s and y != g:
                        found[y] = ready
                        break
            for y in sorted(found):
                out.append((x, y, (mis, int(g == y), found[y], stuck, needed, 0, deadlock, holding, cover)))
        return out

    def class_arrays(self, resolve: bool = True) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`classes` of a hand-empty state as arrays: blocks, destinations, relations (moves, 9).

        Computed once per state (:func:`~csql_sim.core.state.move_classes.class_arrays`); asked
        again after :meth:`resolve_cover` or :meth:`resolve`, only the cover and ``least-stuck`` are filled in.
        """
        from csql_sim.core.state.move_classes import StateArrays, class_arrays, with_known

        if self.held is not None:
            raise WorldError("the classes of moves as arrays are those of a hand-empty state")
        self._refresh()
        if resolve:
            self.resolve()
        cover = fewest = None
        if self._cover is not None:
            cover = np.zeros(self.n, np.int8)
            cover[list(self._cover)] = 1
        if self._stuck_after is not None:
            fewest, least = np.full(self.n, -1, np.int8), self.least
            for move, count in self._stuck_after.items():
                fewest[move.block] = count == least
        arrays = (self._sup_a, self._above_a, self._goal_a, self._goal_above_a, self._placed_a, self._stuck_mask)
        if self._classes is None:
            self._classes = class_arrays(StateArrays(*arrays, None, None))
        return with_known(*self._classes, StateArrays(*arrays, cover, fewest))

    def misplaced(self) -> int:
        """The number of misplaced blocks."""
        return self.placed.count(False)


class KeptRelations:
    """The move relations of the last state asked about, moved on by the action chosen there.

    A policy asks :meth:`of` for the relations of each state and tells :meth:`chose` the action
    it took; when the next state is where that action leads, the kept tracker is updated by it
    instead of being computed from scratch. Either way the relations are exactly ``state``'s
    (a cache of derived facts, not a memory of visited states: the same state gives the same action).
    """

    def __init__(self) -> None:
        self._tracker: RelationTracker | None = None
        self._pending: Action | None = None

    def chose(self, action: Action | None) -> None:
        """The action taken in the state last asked about (None: nothing to move on)."""
        self._pending = action

    def of(self, state: State, target: State) -> RelationTracker:
        """The move relations of ``state`` towards ``target``."""
        tracker, pending = self._tracker, self._pending
        self._pending = None
        if tracker is not None and pending is not None and tracker.goal == target.support:
            try:
                tracker.apply(pending)
            except WorldError:
                tracker = None
            if tracker is not None and tracker.sup == list(state.support):
                return tracker
        self._tracker = RelationTracker(state, target)
        return self._tracker
