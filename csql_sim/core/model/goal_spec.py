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
"""

from __future__ import annotations

import functools
from collections import deque
from dataclasses import dataclass, field

from csql_sim.core.model.transition_table import true_table
from csql_sim.core.state.world import HAND, TABLE, BlocksWorld, State, WorldError, all_states, block_name

Atom = tuple[str, tuple[int, ...]]
"""``(predicate, block indices)``; ``TABLE`` stands for the table in ``on``."""
PREDICATES = {"on": 2, "clear": 1, "holding": 1, "handempty": 0}
"""The canonical predicates and their arities."""


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
    """An atom in PDDL form, ``(on a b)``, with ``names`` for the blocks (default: lower-case letters)."""
    pred, args = atom

    def name(i: int) -> str:
        if i == TABLE:
            return "table"
        return names[i] if names is not None else block_name(i).lower()

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
        if not self.states:
            raise GoalError(f"no state of the {self.n}-block world satisfies the goal {self.text()}")

    @classmethod
    def of_state(cls, state: State, names: tuple[str, ...] | None = None) -> GoalSpec:
        """The full goal of one state."""
        return cls(state.n, state_atoms(state), names=names)

    def satisfied(self, state: State | None) -> bool:
        """Whether ``state`` satisfies every positive atom and no negated one (None: nothing perceived)."""
        if state is None:
            return False
        return all(holds(a, state) for a in self.positive) and not any(holds(a, state) for a in self.negative)

    @functools.cached_property
    def states(self) -> tuple[State, ...]:
        """Every state that satisfies the goal, in the stable state order."""
        return tuple(s for s in all_states(self.n) if self.satisfied(s))

    @property
    def partial(self) -> bool:
        """True when more than one state satisfies the goal."""
        return len(self.states) > 1

    def nearest(self, state: State) -> State:
        """The satisfying state fewest actions away from ``state`` (ties: the stable action order)."""
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
