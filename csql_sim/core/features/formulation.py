"""A blocks-world formulation read from its PDDL domain: the predicates the feature grammar reads.

The feature grammar (:mod:`csql_sim.core.features.grammar`) builds its concepts and roles
from a domain's own predicates, under the domain's own names: it never sees csql-sim's
names for them. A :class:`Formulation` is that vocabulary, read from a PDDL domain with
the ``pddl`` package:

* its predicates, names and arities as the domain writes them, and the **goal versions**
  (name + ``_g``) of those a goal configuration is written in (``on``, ``on-table``);
* its constants (``table`` in the one-operator move domain: the table is an object there);
* whether a move is a pick and a put with a hand between them (``hand``: the four-operator
  domain) or a single action (the move domain).

The one place csql-sim's meaning of a predicate is used is :func:`primitive_arrays`, which
writes a state as the domain's atoms: each predicate's *role* (on, on the table, clear,
holding, hand empty, block) is recognized from its spelling as :mod:`~csql_sim.core.files.pddl_import`
recognizes it when it reads a problem of that domain. The grammar, the learner and the
classifiers see only the atoms.

Two domains ship (:data:`BUILTIN`): ``4op`` (``assets/domains/blocks-4op.pddl``, IPC's
pick-up, put-down, stack, unstack) and ``move`` (``assets/domains/blocks-move.pddl``,
``move ?b ?from ?to``).
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable, Mapping
from dataclasses import dataclass

import numpy as np

from csql_sim.core.files.pddl_import import (
    ARITY,
    PREDICATE_ALIASES,
    TABLE_NAME,
    PddlImportError,
    domain_actions,
    parse_domain_text,
)
from csql_sim.core.state.world import HAND, TABLE, State
from csql_sim.infra.assets import asset_text
from csql_sim.infra.files import read_text_file

BUILTIN = {"4op": "blocks-4op.pddl", "move": "blocks-move.pddl"}
"""The shipped formulations: name -> domain file in ``assets/domains``."""
GOAL_SUFFIX = "_g"
GOAL_ROLES = ("on", "ontable")
"""The roles a goal configuration is written in: their predicates get goal versions."""
MAX_DOMAIN_BYTES = 1 << 20


@dataclass(frozen=True)
class Predicate:
    """A predicate of the domain: its name as written (lower case), arity and role."""

    name: str
    arity: int
    role: str


@dataclass(frozen=True)
class Formulation:
    """A blocks-world domain's vocabulary (module docstring).

    Attributes:
        name: ``4op``, ``move`` or the domain's own name.
        predicates: the domain's predicates, goal versions included (their role is the predicate's).
        constants: the domain's constants, objects after the blocks (the table of the move domain).
        hand: whether a move is a pick and a put with a held block between them.
    """

    name: str
    predicates: tuple[Predicate, ...]
    constants: tuple[str, ...]
    hand: bool

    @property
    def table_object(self) -> bool:
        """Whether the table is an object (the last constant) rather than the absence of a support."""
        return TABLE_NAME in self.constants


def load_formulation(name_or_path: str) -> Formulation:
    """A shipped formulation by name (``4op``, ``move``), or the domain in a PDDL file."""
    if name_or_path in BUILTIN:
        return parse_formulation(asset_text("domains", BUILTIN[name_or_path]), name_or_path, name_or_path)
    text = read_text_file(name_or_path, MAX_DOMAIN_BYTES, "PDDL domain")
    return parse_formulation(text, os.fspath(name_or_path))


def parse_formulation(text: str, source: str, name: str | None = None,
                      roles: Mapping[str, str] | None = None) -> Formulation:
    """The formulation of a domain's text; PddlImportError names what is not a blocks world.

    The predicates come in the order the domain declares them, so the features generated from
    them (:mod:`~csql_sim.core.features.generate`) depend on the domain alone, not on how its
    predicates are spelled. ``roles`` gives each predicate's role (``on``, ``ontable``, ``clear``,
    ``holding``, ``handempty``, ``block``) where the domain spells them otherwise; by default
    the role is recognized from the spelling.
    """
    domain = parse_domain_text(text, source)
    actions = domain_actions(domain, source)
    preds = []
    for p in sorted(domain.predicates, key=_declared(text)):
        role = (roles or PREDICATE_ALIASES).get(p.name)
        if role is None or ARITY[role] != p.arity:
            raise PddlImportError(f"{source}: predicate {p.name}/{p.arity} is not one of the blocks world's")
        preds.append(Predicate(p.name, p.arity, role))
    preds += [Predicate(p.name + GOAL_SUFFIX, p.arity, p.role) for p in list(preds) if p.role in GOAL_ROLES]
    constants = tuple(sorted(c.name for c in domain.constants))
    if constants not in ((), (TABLE_NAME,)):
        raise PddlImportError(f"{source}: constants {', '.join(constants)}: only a table object is known")
    hand = any(p.role in ("holding", "handempty") for p in preds)
    if hand == (TABLE_NAME in constants) or any(a.startswith("move") for a in actions) == hand:
        raise PddlImportError(f"{source}: expected either a hand (holding, pick-up ...) or a table object "
                              "with move actions")
    return Formulation(name or domain.name, tuple(preds), constants, hand)


def _declared(text: str) -> Callable[[object], tuple[int, str]]:
    """The sort key of a parsed predicate: where the domain's ``:predicates`` declares it (then its name)."""
    lowered = text.lower()
    section = lowered[max(lowered.find(":predicates"), 0):]

    def key(p: object) -> tuple[int, str]:
        name = str(getattr(p, "name", ""))
        found = re.search(r"\(\s*" + re.escape(name) + r"[\s)]", section)
        return (found.start() if found else len(section), name)
    return key


def primitive_arrays(form: Formulation, states: list[State], targets: list[State]
                     ) -> tuple[dict[str, np.ndarray], int]:
    """Every predicate's extension in every (state, target) pair, as arrays; and the object count.

    Objects are the blocks (``0..n-1``) then the constants. A unary predicate gives a bool
    array (pairs, objects), a binary one (pairs, objects, objects), a nullary one (pairs,).
    Goal versions read the target. All states have the same number of blocks.
    """
    sup = np.array([s.support for s in states], np.int64)
    goal = np.array([t.support for t in targets], np.int64)
    return support_arrays(form, sup, goal)


def support_arrays(form: Formulation, sup: np.ndarray, goal: np.ndarray) -> tuple[dict[str, np.ndarray], int]:
    """:func:`primitive_arrays` of states and targets given as support arrays (pairs, n).

    ``goal`` may have one row, the target of every pair: the goal predicates then have one row.
    """
    n = sup.shape[1]
    objects = n + len(form.constants)
    out = {}
    for p in form.predicates:
        source = goal if p.name.endswith(GOAL_SUFFIX) and p.role in GOAL_ROLES else sup
        out[p.name] = _extension(p.role, source, objects, n)
    return out, objects


def _extension(role: str, sup: np.ndarray, objects: int, n: int) -> np.ndarray:
    """The extension of one role over supports ``sup`` (pairs, n)."""
    pairs = sup.shape[0]
    blocks = np.zeros((pairs, objects), bool)
    blocks[:, :n] = True
    if role == "block":
        return blocks
    if role == "ontable":
        return np.pad(sup == TABLE, ((0, 0), (0, objects - n)))
    if role == "holding":
        return np.pad(sup == HAND, ((0, 0), (0, objects - n)))
    if role == "handempty":
        return ~(sup == HAND).any(1)
    if role == "on":
        on = np.zeros((pairs, objects, objects), bool)
        rows, cols = np.nonzero(sup >= 0)
        on[rows, cols, sup[rows, cols]] = True
        if objects > n:  # the table object: a block on the table is on it
            rows, cols = np.nonzero(sup == TABLE)
            on[rows, cols, n] = True
        return on
    # clear: a block with nothing on it and not held; the table object is always clear
    covered = np.zeros((pairs, objects), bool)
    rows, cols = np.nonzero(sup >= 0)
    covered[rows, sup[rows, cols]] = True
    clear = ~covered & ~np.pad(sup == HAND, ((0, 0), (0, objects - n)))
    return clear


__all__ = ["BUILTIN", "GOAL_SUFFIX", "Formulation", "Predicate", "load_formulation", "parse_formulation",
           "primitive_arrays", "support_arrays"]
