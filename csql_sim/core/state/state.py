"""One configuration of n blocks, for every n from 1 to thousands: the relation ``on`` with names.

A state says, for every block, what it stands on: the table, another block, or the
gripper (held). At most one block is held. States are immutable and hashable; their
identity is the support tuple (the names ride along and do not take part in equality).

Views of a state: for n <= 6 the enumerated world (:mod:`csql_sim.core.state.world`: the ground
index and the paper's messages); for 7..26 the relational message
(:mod:`csql_sim.core.state.relational_message`); past 26 no message.

**Names.** Each block carries the user's name (:attr:`State.names`, e.g. the objects of a
PDDL file, as written there; compare them without case with :func:`same_name`). Without
names a block is called by its default name (:func:`default_name`): ``A`` .. ``Z`` for the
first 26, then ``AA``, ``AB``, ... (as spreadsheet columns), so that a block's default name
depends on its index only. The configuration notation (``CBA``, ``A,B,C``, ``B,C+A``) uses
the letters; past 26 blocks, or with names of more than one character, blocks inside a
tower are separated by spaces (:func:`format_config`).
"""

from __future__ import annotations

import functools
import string
from dataclasses import dataclass, field

from csql_sim.infra.errors import CsqlError

TABLE = -1
"""Support value: the block stands on the table."""
HAND = -2
"""Support value: the block is held by the gripper."""
LETTERS = string.ascii_uppercase
"""The configuration notation's letters: blocks A-Z (26 at most)."""
MAX_LETTERS = len(LETTERS)
MIN_LETTERS = 2
"""The notation writes 2..26 blocks (one letter each)."""


class WorldError(CsqlError):
    """A state, action or configuration that does not exist in the blocks world."""


def check_letters_n(n: int) -> int:
    """Return ``n`` if the letter notation can write n blocks (2..26), else raise WorldError."""
    if not isinstance(n, int) or isinstance(n, bool) or not MIN_LETTERS <= n <= MAX_LETTERS:
        raise WorldError(f"number of blocks must be {MIN_LETTERS}..{MAX_LETTERS}, got {n!r}")
    return n


def default_name(i: int) -> str:
    """The default name of block ``i``: ``A`` .. ``Z``, then ``AA``, ``AB``, ... (``i`` from 0)."""
    out = ""
    i += 1
    while i > 0:
        i, rem = divmod(i - 1, MAX_LETTERS)
        out = LETTERS[rem] + out
    return out


@functools.cache
def default_names(n: int) -> tuple[str, ...]:
    """The default names of n blocks (the letters for n <= 26)."""
    return tuple(default_name(i) for i in range(n))


def same_name(a: str, b: str) -> bool:
    """Whether two block names are the same name (compared without case, as PDDL does)."""
    return a.casefold() == b.casefold()


@dataclass(frozen=True)
class State:
    """One configuration of n >= 1 blocks.

    Attributes:
        support: ``support[i]`` is what block ``i`` stands on: :data:`TABLE`,
            :data:`HAND`, or the index of the block beneath it.
        names: the blocks' names (as the user wrote them), or None for the default names;
            not part of the state's identity (equality and hash use ``support`` only).
    """

    support: tuple[int, ...]
    names: tuple[str, ...] | None = field(default=None, compare=False, repr=False)

    def __post_init__(self) -> None:
        if self.names is not None:
            _validate_names(self.names, len(self.support))
        _validate_support(self.support, self.names)

    @property
    def n(self) -> int:
        """Number of blocks."""
        return len(self.support)

    @property
    def block_names(self) -> tuple[str, ...]:
        """The names of the blocks: :attr:`names`, or the default names."""
        return self.names if self.names is not None else default_names(self.n)

    def name(self, i: int) -> str:
        """The name of block ``i``."""
        return self.names[i] if self.names is not None else default_name(i)

    def index_of(self, name: str) -> int:
        """The block called ``name`` (compared without case); raises WorldError if there is none."""
        for i, own in enumerate(self.block_names):
            if same_name(own, name):
                return i
        raise WorldError(f"no block is called {name!r}")

    def named(self, names: tuple[str, ...] | None) -> State:
        """This configuration with other names (None: the default names)."""
        return State(self.support, None if names is None else tuple(names))

    def with_support(self, support: tuple[int, ...]) -> State:
        """Another configuration of the same, named blocks."""
        return State(support, self.names)

    def with_changes(self, support: tuple[int, ...], changed: tuple[int, ...]) -> State:
        """Another configuration of the same blocks that differs from this one only at ``changed`` (the caller's word).

        Checked there alone (:func:`_validate_changes`, O(n) in C plus the changed blocks' towers
        in Python): a successor of a plan of hundreds of blocks is not validated block by block.
        """
        if len(support) != self.n:
            return self.with_support(support)
        _validate_changes(support, changed, self.names)
        out = object.__new__(State)
        object.__setattr__(out, "support", support)
        object.__setattr__(out, "names", self.names)
        return out

    @functools.cached_property
    def above_of(self) -> tuple[int | None, ...]:
        """``above_of[i]``: the block standing directly on block ``i``, or None."""
        out: list[int | None] = [None] * self.n
        for j, s in enumerate(self.support):
            if s >= 0:
                out[s] = j
        return tuple(out)

    @functools.cached_property
    def held(self) -> int | None:
        """Index of the held block, or None when the hand is empty."""
        return self.support.index(HAND) if HAND in self.support else None

    def above(self, i: int) -> int | None:
        """The block standing directly on block ``i``, or None."""
        return self.above_of[i]

    def is_clear(self, i: int) -> bool:
        """True when nothing stands on block ``i`` and it is not held (the paper's clear)."""
        return self.support[i] != HAND and self.above_of[i] is None

    def clear(self) -> tuple[bool, ...]:
        """:meth:`is_clear` of every block."""
        return tuple(self.is_clear(i) for i in range(self.n))

    def towers(self) -> tuple[tuple[int, ...], ...]:
        """Towers bottom-up, sorted by their bottom block."""
        out = []
        for i, s in enumerate(self.support):
            if s == TABLE:
                tower = [i]
                while (top := self.above_of[tower[-1]]) is not None:
                    tower.append(top)
                out.append(tuple(tower))
        return tuple(out)

    def notation(self) -> str:
        """The canonical configuration notation with the default names, e.g. ``A,CB+D`` (parseable, compared)."""
        return format_config(self)

    def named_notation(self) -> str:
        """The configuration notation with the blocks' own names (see :func:`format_config`).

        What messages and reports show people: a state that carries its problem's names
        (:attr:`names`, e.g. a PDDL problem's objects, passed down from the start state
        through every successor) is shown in them; without names it is :meth:`notation`.
        """
        return format_config(self, self.block_names)

    def to_json(self) -> dict:
        """``{"support": [...], "names": [...] | null}``: the state for a JSON report."""
        return {"support": list(self.support), "names": None if self.names is None else list(self.names)}

    @classmethod
    def from_json(cls, doc: dict) -> State:
        """Inverse of :meth:`to_json` (raises WorldError on a malformed object)."""
        try:
            support = tuple(int(s) for s in doc["support"])
            names = doc.get("names")
            return cls(support, None if names is None else tuple(str(x) for x in names))
        except (KeyError, TypeError, ValueError, AttributeError) as exc:
            raise WorldError(f"not a state object: {exc}") from None

    def __str__(self) -> str:
        return self.notation()


def _validate_support(support: tuple[int, ...], names: tuple[str, ...] | None = None) -> None:
    """Raise WorldError unless ``support`` is one configuration (checked in O(n)); messages use ``names``."""
    n = len(support)

    def called(i: int) -> str:
        return names[i] if names is not None else default_name(i)

    if n < 1:
        raise WorldError("a state needs at least one block")
    if support.count(HAND) > 1:
        raise WorldError("more than one block is held")
    under: set[int] = set()
    for i, s in enumerate(support):
        if s in (TABLE, HAND):
            continue
        if s == i:
            raise WorldError(f"block {called(i)} stands on itself")
        if not isinstance(s, int) or not 0 <= s < n:
            raise WorldError(f"block {called(i)} stands on an invalid support {s!r}")
        if s in under:
            raise WorldError(f"two blocks stand on block {called(s)}")
        if support[s] == HAND:
            raise WorldError(f"block {called(i)} stands on the held block")
        under.add(s)
    grounded = [s in (TABLE, HAND) for s in support]
    for i in range(n):
        path, j = [], i
        while not grounded[j]:
            path.append(j)
            j = support[j]
            if len(path) > n:
                raise WorldError("the blocks form a cycle")
        for k in path:
            grounded[k] = True


def _validate_changes(support: tuple[int, ...], changed: tuple[int, ...], names: tuple[str, ...] | None) -> None:
    """Raise WorldError unless ``support``, valid before ``changed`` moved, is valid (as :func:`_validate_support`).

    An unchanged block keeps its support, so a new fault involves a changed block: two blocks on
    one support, a block on the held one, a second held block, or a cycle through it.
    """
    n = len(support)
    if support.count(HAND) > 1:
        raise WorldError("more than one block is held")
    for i in changed:
        s = support[i]
        called = names[i] if names is not None else default_name(i)
        if s == HAND:
            if i in support:
                raise WorldError(f"a block stands on the held block {called}")
            continue
        if s == TABLE:
            continue
        if not isinstance(s, int) or not 0 <= s < n or s == i:
            raise WorldError(f"block {called} stands on an invalid support {s!r}")
        if support.count(s) > 1:
            raise WorldError(f"two blocks stand on block {names[s] if names is not None else default_name(s)}")
        if support[s] == HAND:
            raise WorldError(f"block {called} stands on the held block")
        j, steps = s, 0
        while j >= 0:
            if j == i or steps > n:
                raise WorldError("the blocks form a cycle")
            j, steps = support[j], steps + 1


@functools.lru_cache(maxsize=16)
def _validate_names(names: tuple[str, ...], n: int) -> None:
    """Raise WorldError unless ``names`` are ``n`` distinct words (remembered: every successor repeats them)."""
    if len(names) != n:
        raise WorldError(f"{len(names)} names for {n} blocks")
    seen: set[str] = set()
    for name in names:
        if not isinstance(name, str) or not name or any(ch.isspace() or ch in "(),+;" for ch in name):
            raise WorldError(f"block name {name!r}: expected a word without spaces, brackets, ',', '+' or ';'")
        if name.casefold() in seen:
            raise WorldError(f"block name {name!r} is given twice (names compare without case)")
        seen.add(name.casefold())


def format_config(state: State, names: tuple[str, ...] | None = None) -> str:
    """Towers bottom-up, sorted by their bottom block and comma-joined, ``+X`` if holding X.

    With one-character names (the letters, n <= 26) a tower is its names run together
    (``CBA``); otherwise its names are separated by spaces and towers by ``, ``
    (``b3 b1, b2 + b4``).
    """
    names = default_names(state.n) if names is None else names
    short = all(len(x) == 1 for x in names)
    inside, between, plus = ("", ",", "+") if short else (" ", ", ", " + ")
    towers = between.join(inside.join(names[i] for i in t) for t in state.towers())
    held = state.held
    return towers + (f"{plus}{names[held]}" if held is not None else "")
