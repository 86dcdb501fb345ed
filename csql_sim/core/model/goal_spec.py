"""Goals as sets of atoms: a full goal is one state, a partial goal a set of states.

A PDDL goal is a conjunction of atoms; csql-sim's executor and planners take one goal
*state*. :class:`GoalSpec` bridges the two:

* an atom is ``(predicate, arguments)`` over block indices, in the blocks world's own
  vocabulary: ``("on", (x, y))`` (``y`` a block, or :data:`~csql_sim.core.state.world.TABLE`
  for the table), ``("clear", (x,))``, ``("holding", (x,))`` and ``("handempty", ())``;
* :meth:`GoalSpec.satisfied` says whether a state satisfies every positive atom and no
  negated one; success on the arm is this test on the **perceived** state;
* :meth:`GoalSpec.states` lists the states that satisfy it (one for a full goal);
* :meth:`GoalSpec.nearest` is the goal state a planner aims for from a state: the first
  satisfying state a breadth-first search from that state meets over the true transitions
  (fewest actions; ties broken by the stable action order), so a plan to it is an optimal
  plan for the whole goal set.

Past six blocks (relational :class:`~csql_sim.core.state.world.State` states)
the satisfying states are not listed: :meth:`GoalSpec.nearest` is then a *target*
configuration derived from the given state (:func:`goal_target`): every block the goal
places stands where the goal says, every other block keeps its support where that is
consistent with the goal, else stands on the table (a short backtracking search settles
negated atoms). The satisfiability check is the same search.
"""

from __future__ import annotations

import functools
from collections import deque
from dataclasses import dataclass, field

from csql_sim.core.model.transition_table import true_table
from csql_sim.core.state.state import default_name
from csql_sim.core.state.world import HAND, MAX_BLOCKS, TABLE, BlocksWorld, State, WorldError, all_states

Atom = tuple[str, tuple[int, ...]]
"""``(predicate, block indices)``; ``TABLE`` stands for the table in ``on``."""
PREDICATES = {"on": 2, "clear": 1, "holding": 1, "handempty": 0}
"""The canonical predicates and their arities."""
TARGET_SEARCH_LIMIT = 200_000
"""The most partial assignments :func:`goal_target` tries before it gives up (negated atoms only)."""


class GoalError(WorldError):
    """A goal no state of the blocks world satisfies, or an atom that is not one."""


def holds(atom: Atom, state: State) -> bool:
    """Whether ``atom`` is true in ``state``."""
    pred, args = atom
    if pred == "on":
        return state.support[args[0]] == args[1]
    if pred == "clear":
        return state.is_clear(args[0])
    if pred == "holding":
        return state.support[args[0]] == HAND
    if pred == "handempty":
        return state.held is None
    raise GoalError(f"unknown predicate {pred!r}")


def atom_text(atom: Atom, names: tuple[str, ...] | None = None) -> str:
    """An atom in PDDL form, ``(on a b)``, with ``names`` for the blocks (default: ``a`` .. ``z``, ``aa``, ...)."""
    pred, args = atom

    def name(i: int) -> str:
        if i == TABLE:
            return "table"
        return names[i] if names is not None else default_name(i).lower()

    if pred == "on" and args[1] == TABLE:
        return f"(ontable {name(args[0])})"
    return "(" + " ".join([pred, *(name(i) for i in args)]) + ")"


def state_atoms(state: State) -> frozenset[Atom]:
    """The atoms that pin ``state`` down: where every block is, and an empty hand if it is."""
    atoms: set[Atom] = {("handempty", ())} if state.held is None else set()
    for i, s in enumerate(state.support):
        atoms.add(("holding", (i,)) if s == HAND else ("on", (i, s)))
    return frozenset(atoms)


@dataclass(frozen=True)
class GoalSpec:
    """A goal as positive and negated atoms over ``n`` blocks.

    Attributes:
        n: number of blocks.
        positive: atoms that must hold.
        negative: atoms that must not hold.
        names: the blocks' names in messages (PDDL object names; default lower-case letters).
    """

    n: int
    positive: frozenset[Atom]
    negative: frozenset[Atom] = frozenset()
    names: tuple[str, ...] | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        for pred, args in self.positive | self.negative:
            if PREDICATES.get(pred) != len(args) or any(not (0 <= a < self.n or a == TABLE) for a in args):
                raise GoalError(f"({pred} {' '.join(map(str, args))}) is not an atom of the {self.n}-block world")
        if self.enumerated:
            if not self.states:
                raise GoalError(f"no state of the {self.n}-block world satisfies the goal {self.text()}")
        else:
            goal_target(self, State((TABLE,) * self.n))

    @classmethod
    def of_state(cls, state: State, names: tuple[str, ...] | None = None) -> GoalSpec:
        """The full goal of one state."""
        return cls(state.n, state_atoms(state), names=names)

    @property
    def enumerated(self) -> bool:
        """Whether the goal's states are listed (n <= 6); past six only targets are derived."""
        return self.n <= MAX_BLOCKS

    def satisfied(self, state: State | None) -> bool:
        """Whether ``state`` satisfies every positive atom and no negated one (None: nothing perceived)."""
        if state is None:
            return False
        return all(holds(a, state) for a in self.positive) and not any(holds(a, state) for a in self.negative)

    @functools.cached_property
    def states(self) -> tuple[State, ...] | tuple[State, ...]:
        """Every state that satisfies the goal, in the stable state order.

        Past six blocks only a full goal lists its one state; a partial one raises GoalError.
        """
        if self.enumerated:
            return tuple(s for s in all_states(self.n) if self.satisfied(s))
        if self.partial:
            raise GoalError(f"the states of a partial goal of {self.n} blocks are not listed")
        return (goal_target(self, State((TABLE,) * self.n)),)

    @property
    def partial(self) -> bool:
        """True when more than one state satisfies the goal."""
        if self.enumerated:
            return len(self.states) > 1
        return len({args[0] for pred, args in self.positive if pred in ("on", "holding")}) < self.n

    @property
    def count(self) -> int | None:
        """How many states satisfy the goal (None: a partial goal past six blocks, not counted)."""
        return len(self.states) if self.enumerated or not self.partial else None

    def nearest(self, state: State) -> State:
        """The satisfying state fewest actions away from ``state`` (ties: the stable action order).

        Past six blocks: the target :func:`goal_target` derives from ``state``.
        """
        if not self.enumerated:
            return goal_target(self, state)
        if len(self.states) == 1:
            return self.states[0]
        return _nearest(self, state)

    def unsatisfied(self, state: State) -> list[str]:
        """The goal's atoms that ``state`` violates, in PDDL form."""
        pos = sorted(atom_text(a, self.names) for a in self.positive if not holds(a, state))
        return pos + sorted(f"(not {atom_text(a, self.names)})" for a in self.negative if holds(a, state))

    def atom_texts(self) -> list[str]:
        """The atoms in PDDL form, positive ones first, each group sorted."""
        pos = sorted(atom_text(a, self.names) for a in self.positive)
        return pos + sorted(f"(not {atom_text(a, self.names)})" for a in self.negative)

    def text(self) -> str:
        """The goal in one line: its atoms, space-separated."""
        return " ".join(self.atom_texts()) or "(and)"


def _nearest(goal: GoalSpec, start: State) -> State:
    """Breadth-first search from ``start`` on the true world to the first state satisfying ``goal``."""
    world, table = BlocksWorld.of(start.n), true_table(start.n)
    first = world.state_index(start)
    seen, queue = {first}, deque([first])
    while queue:
        s = queue.popleft()
        if goal.satisfied(world.states[s]):
            return world.states[s]
        for a in table.legal[s]:
            nxt = int(table.rows[s][a])
            if nxt not in seen:
                seen.add(nxt)
                queue.append(nxt)
    raise GoalError(f"no state satisfying {goal.text()} is reachable from {start.notation()}")


def goal_target(goal: GoalSpec, state: State) -> State:
    """A configuration satisfying ``goal`` that keeps as much of ``state`` as the goal allows.

    A block the goal places (an ``on`` or ``holding`` atom) stands there. Every other block
    counts as well placed where it stands: it keeps its support in ``state`` when it need not
    move, that is when it stands on the table, or on a block that is itself well placed (kept,
    or placed by the goal where it stands, down to the table) and that no placed block claims,
    the goal does not require clear and is not to be held; else it stands on the table (a block
    that must move anyway goes where one move takes it). Negated atoms this leaves false are
    met by a depth-first search over the other supports (table, blocks, hand, in that order; at
    most :data:`TARGET_SEARCH_LIMIT` tries).

    Raises:
        GoalError: no configuration satisfies the goal (or none was found within the limit).
    """
    n, fixed = goal.n, _placed(goal)
    cleared = {args[0] for pred, args in goal.positive if pred == "clear"}
    flat = [fixed.get(i, TABLE) for i in range(n)]
    if not _valid(flat) or not goal_holds_in(goal, State(tuple(flat))):
        raise GoalError(f"no state of the {n}-block world satisfies the goal {goal.text()}")
    support = _kept_supports(state, fixed, cleared)
    while (loop := _cycle(support)) is not None:  # a cycle always holds a block the goal does not place
        support[next(i for i in loop if i not in fixed)] = TABLE
    if goal.satisfied(State(tuple(support))):
        return State(tuple(support))
    options = [(fixed[i],) if i in fixed else tuple(dict.fromkeys(
        s for s in (support[i], TABLE, *range(n), HAND) if s != i and s not in cleared)) for i in range(n)]
    tries = [0]
    found = _assign(goal, options, [], set(), tries)
    if found is None:
        more = f" (gave up after {TARGET_SEARCH_LIMIT} tries)" if tries[0] > TARGET_SEARCH_LIMIT else ""
        raise GoalError(f"no state of the {n}-block world satisfies the goal {goal.text()}{more}")
    return State(found)


def goal_holds_in(goal: GoalSpec, state: State) -> bool:
    """Whether every positive atom of ``goal`` holds in ``state``."""
    return all(holds(a, state) for a in goal.positive)


def _placed(goal: GoalSpec) -> dict[int, int]:
    """Block -> support for the blocks the goal's ``on`` and ``holding`` atoms place."""
    fixed: dict[int, int] = {}
    for pred, args in goal.positive:
        if pred in ("on", "holding"):
            where = args[1] if pred == "on" else HAND
            if fixed.setdefault(args[0], where) != where:
                raise GoalError(f"no state of the {goal.n}-block world satisfies the goal {goal.text()}")
    return fixed


def _kept_supports(state: State, fixed: dict[int, int], cleared: set[int]) -> list[int]:
    """The target's supports: placed blocks where the goal puts them, free ones kept where well placed.

    Each tower of ``state`` is walked bottom-up, carrying whether the block below is well
    placed (it keeps its support, and so does everything under it); O(n).
    """
    claimed = set(fixed.values()) | cleared | {b for b, where in fixed.items() if where == HAND}
    support = [fixed.get(i, TABLE) for i in range(state.n)]  # the held block: placed, or onto the table
    for tower in state.towers():
        well = True  # the table
        for i in tower:
            below = state.support[i]
            if i in fixed:
                well = well and fixed[i] == below
                continue
            well = below == TABLE or (well and below not in claimed)
            support[i] = below if well else TABLE
    return support


def _cycle(support: list[int]) -> list[int] | None:
    """The blocks of a cycle of supports, if there is one (each block visited once: O(n))."""
    done = [False] * len(support)
    for i in range(len(support)):
        path, on_path, j = [], set(), i
        while j >= 0 and not done[j] and j not in on_path:
            path.append(j)
            on_path.add(j)
            j = support[j]
        if j >= 0 and j in on_path:
            return path[path.index(j):]
        for k in path:
            done[k] = True
    return None


def _valid(support: list[int]) -> bool:
    try:
        State(tuple(support))
    except WorldError:
        return False
    return True


def _assign(goal: GoalSpec, options: list, chosen: list[int], used: set[int], tries: list[int]) -> tuple | None:
    """Depth-first: the first full assignment of supports that is a state satisfying ``goal``.

    Checking a full assignment counts one try per block, so the limit bounds the work at any
    n. The search keeps its own stack (one iterator of options per chosen block), so a world of
    thousands of blocks does not recurse thousands deep.
    """
    stack = [iter(options[len(chosen)])] if len(chosen) < goal.n else []
    if not stack:
        return tuple(chosen) if _valid(chosen) and goal.satisfied(State(tuple(chosen))) else None
    while stack:
        s = next(stack[-1], None)
        if s is None:  # this block's options are spent: back to the one before
            stack.pop()
            if chosen:
                used.discard(chosen.pop())
            continue
        tries[0] += 1
        if tries[0] > TARGET_SEARCH_LIMIT:
            return None
        if s in used or (s == HAND and ("handempty", ()) in goal.positive):
            continue
        if len(chosen) + 1 == goal.n:
            tries[0] += goal.n  # checking a full assignment costs a try per block
            full = [*chosen, s]
            if _valid(full) and goal.satisfied(State(tuple(full))):
                return tuple(full)
            continue
        chosen.append(s)
        if s != TABLE:
            used.add(s)
        stack.append(iter(options[len(chosen)]))
    return None
