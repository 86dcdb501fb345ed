"""Blocks-world PDDL problems as csql-sim tasks: the cubes, the start state and the goal.

Problems (and optionally their domain) are read with the ``pddl`` package's parsers. PDDL
is case-insensitive and that parser is not (it refuses ``:INIT``, as IPC 2000's files
write it), so the text is lower-cased first; object names are therefore reported in lower
case.

**Domains** (a domain file is optional; without one the problem's predicates decide):

* ``4op``: the paper's four operators, IPC's ``pick-up``, ``put-down``, ``stack``,
  ``unstack`` with ``on``, ``ontable``, ``clear``, ``handempty``, ``holding``;
* ``move``: the hand-less variants, either the three operators ``move-b-to-b``,
  ``move-b-to-t`` (alias ``move-to-t``), ``move-t-to-b`` with ``on``, ``on-table``,
  ``clear``, or the one operator ``move ?b ?from ?to`` (and ``move-to-table ?b ?from``)
  with the table an object named ``table``; each move is executed as a pick and a put;
* ``csql``: csql-sim's own export (``csql-sim pddl``), whose facts are message fields
  (``on_a_b``, ``clear_a_1``, ``held_0``) and whose actions are ``unstack_a_b`` and so on.

Predicate spellings accepted: ``ontable``/``on-table``/``on_table``, ``handempty``/
``hand-empty``/``arm-empty``/``armempty``/``emptyhand``, and ``block ?x`` as a type test.

**Names.** The blocks are the problem's objects and the domain's constants, less the
table (an object named ``table`` or of type ``table``), sorted by name (numbers inside
names compare as numbers: ``b2`` before ``b10``); the first is cube A, the next B, and so
on, whatever order the file lists them in. Between 2 and 26 blocks by default (letters A-Z);
``max_blocks`` reads up to :data:`MAX_PLANNED_BLOCKS`, named past Z as ``AA``, ``AB``, ...
(planning alone, ``plan --problem``; the arm's commands read as many and take at most 30 cubes).
:attr:`BlocksProblem.objects` are the names in lower case
(as the parser reads them; PDDL names compare without case); the start state carries them
as written in the file (:attr:`BlocksProblem.names`, the first spelling of each).

**Refused** with one line (:class:`PddlImportError`): unknown predicates, more than 26
blocks, an initial state that is not exactly one configuration (a block placed twice or
nowhere, ``clear`` atoms that disagree with the towers, two blocks held), a goal that is
not a conjunction of atoms and negated atoms, or one no state satisfies. A goal that
leaves blocks free is a *partial* goal: a set of states (:class:`~csql_sim.core.model.goal_spec.GoalSpec`).
In the ``move`` variants there is no hand, so their goals imply an empty hand.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, replace

from csql_sim.core.model.goal_spec import Atom, GoalError, GoalSpec
from csql_sim.core.state.state import MAX_LETTERS, default_name
from csql_sim.core.state.world import HAND, MIN_BLOCKS, TABLE, State, WorldError
from csql_sim.infra.errors import CsqlError, shortened
from csql_sim.infra.files import read_text_file

MAX_PDDL_BYTES = 1 << 20
"""The largest PDDL file read (1 MiB)."""
MAX_PLANNED_BLOCKS = 2000
"""The most objects read for planning alone (``read_problem(..., max_blocks=MAX_PLANNED_BLOCKS)``): the limit of
``plan --problem``, ``validate`` and the lifted rules' plans, stated from this constant in help, docs and errors."""
MAX_DRAWN_BLOCKS = 1000
"""The most blocks ``csql-sim problems`` draws per problem (at most :data:`MAX_PLANNED_BLOCKS`: each one plans)."""
TABLE_NAME = "table"
PREDICATE_ALIASES = {"on": "on", "ontable": "ontable", "on-table": "ontable", "on_table": "ontable",
                     "clear": "clear", "holding": "holding", "block": "block",
                     **dict.fromkeys(("handempty", "hand-empty", "arm-empty", "armempty", "emptyhand"), "handempty")}
ARITY = {"on": 2, "ontable": 1, "clear": 1, "holding": 1, "handempty": 0, "block": 1}
DOMAIN_ACTIONS = {
    "4op": {"pick-up": 1, "pickup": 1, "put-down": 1, "putdown": 1, "stack": 2, "unstack": 2},
    "move": {"move-b-to-b": 3, "move-b-to-t": 2, "move-to-t": 2, "move-t-to-b": 2, "move": 3,
             "move-to-table": 2, "move_to_table": 2},
}
CSQL_FACT = re.compile(r"^(clear_[a-f]_[01]|on_[a-f]_[a-f0t]|held_[a-f0])$")
CSQL_ACTION = re.compile(r"^(unstack|stack)_[a-f]_[a-f]$|^(pickup|putdown)_[a-f]$")


class PddlImportError(CsqlError):
    """A PDDL problem or domain csql-sim cannot represent or read."""


@dataclass(frozen=True)
class BlocksProblem:
    """A blocks-world task read from PDDL.

    Attributes:
        name: the problem's name.
        objects: the blocks' PDDL names; ``objects[i]`` is block ``i`` (cube ``LETTERS[i]``).
        start: the initial state (relational past six blocks).
        goal: the goal (full or partial).
        style: ``"4op"``, ``"move"`` or ``"csql"`` (see the module docstring).
        actions: the domain's action names when a domain was read, else None.
        table: the name of the problem's table object (as the parser reads it), or None if it declares none.
    """

    name: str
    objects: tuple[str, ...]
    start: State
    goal: GoalSpec
    style: str
    actions: frozenset[str] | None = None
    table: str | None = None

    @property
    def n(self) -> int:
        """Number of blocks."""
        return len(self.objects)

    @property
    def names(self) -> tuple[str, ...]:
        """The blocks' names as written in the file (the start state's names)."""
        return self.start.block_names

    @property
    def mapping(self) -> dict[str, str]:
        """PDDL object name -> cube letter."""
        return {name: default_name(i) for i, name in enumerate(self.objects)}

    @property
    def index(self) -> dict[str, int]:
        """PDDL object name -> block index, and ``table`` -> TABLE (what plan files may name)."""
        return {**{name: i for i, name in enumerate(self.objects)}, TABLE_NAME: TABLE}

    def mapping_text(self) -> str:
        """``a -> A, b -> B, ...``."""
        return ", ".join(f"{name} -> {cube}" for name, cube in self.mapping.items())


def name_key(name: str) -> list:
    """Sort key of object names: case-insensitive, digit runs compared as numbers (``b2`` < ``b10``).

    A digit run is compared by its length without leading zeros, then its digits: the order
    of numbers, without converting them (a 5,000-digit name would exceed Python's limit).
    """
    return [(len(part.lstrip("0")), part.lstrip("0")) if part.isdigit() else part
            for part in re.split(r"(\d+)", name.lower())]


def read_problem(problem: str | os.PathLike, domain: str | os.PathLike | None = None,
                 max_blocks: int = MAX_LETTERS) -> BlocksProblem:
    """Read a blocks-world problem file (and its domain file, if given) of at most ``max_blocks`` objects.

    Raises:
        PddlImportError: one line naming the file and what cannot be represented.
    """
    source = os.fspath(problem)
    text = read_text_file(problem, MAX_PDDL_BYTES, "PDDL problem")
    domain_text = None if domain is None else read_text_file(domain, MAX_PDDL_BYTES, "PDDL domain")
    dom = None if domain_text is None else _parse_text(domain_text, "domain", os.fspath(domain))
    actions = None if dom is None else domain_actions(dom, os.fspath(domain))
    parsed = _parse_text(text, "problem", source)
    if dom is not None:
        check_agreement(dom, parsed, os.fspath(domain), source)
    problem_ = problem_from_pddl(parsed, source, actions,
                                 constants=() if dom is None else tuple(c.name for c in dom.constants),
                                 max_blocks=max_blocks)
    return with_spelling(problem_, text + "\n" + (domain_text or ""))


def parse_problem_text(text: str, source: str = "problem", domain_text: str | None = None,
                       max_blocks: int = MAX_LETTERS) -> BlocksProblem:
    """:func:`read_problem` on texts instead of files."""
    dom = None if domain_text is None else _parse_text(domain_text, "domain", "domain")
    actions = None if dom is None else domain_actions(dom, "domain")
    parsed = _parse_text(text, "problem", source)
    if dom is not None:
        check_agreement(dom, parsed, "domain", source)
    problem = problem_from_pddl(parsed, source, actions,
                                constants=() if dom is None else tuple(c.name for c in dom.constants),
                                max_blocks=max_blocks)
    return with_spelling(problem, text + "\n" + (domain_text or ""))


def with_spelling(problem: BlocksProblem, text: str) -> BlocksProblem:
    """``problem`` whose start state names its blocks as ``text`` first spells them (PDDL ignores case)."""
    spelled: dict[str, str] = {}
    for word in re.findall(r"[^\s()]+", _strip_comments(text)):
        spelled.setdefault(word.lower(), word)
    names = tuple(spelled.get(name, name) for name in problem.objects)
    return replace(problem, start=problem.start.named(names))


def _strip_comments(text: str) -> str:
    return "\n".join(line.split(";", 1)[0] for line in text.splitlines())


def _parse_text(text: str, kind: str, source: str):  # noqa: ANN202 - a pddl Domain or Problem
    from pddl.parser.domain import DomainParser
    from pddl.parser.problem import ProblemParser

    parser = DomainParser() if kind == "domain" else ProblemParser()
    try:
        return parser(text.lower())
    except Exception as exc:  # lark and pddl raise many types; any is a file we cannot read
        first = next((line.strip() for line in str(exc).splitlines() if line.strip()), type(exc).__name__)
        raise PddlImportError(f"{source}: not a PDDL {kind} the pddl package can read ({shortened(first)})") from None


def parse_domain_text(text: str, source: str = "domain"):  # noqa: ANN201 - a pddl Domain
    """A domain's text parsed by the ``pddl`` package (lower-cased); PddlImportError if it cannot be read."""
    return _parse_text(text, "domain", source)


def domain_actions(domain, source: str) -> frozenset[str]:  # noqa: ANN001 - a pddl Domain
    """The domain's action names, checked to be one of the blocks-world styles."""
    actions = {a.name: len(a.parameters) for a in domain.actions}
    if actions and all(CSQL_ACTION.match(name) and k == 0 for name, k in actions.items()):
        return frozenset(actions)
    for known in DOMAIN_ACTIONS.values():
        if actions and all(known.get(name) == k for name, k in actions.items()):
            return frozenset(actions)
    listed = ", ".join(f"{name}/{k}" for name, k in sorted(actions.items())) or "none"
    raise PddlImportError(f"{source}: actions {listed} are not the blocks world's (pick-up, put-down, stack, "
                          f"unstack) nor its move variant")


def check_agreement(domain, problem, domain_source: str, source: str) -> None:  # noqa: ANN001 - pddl objects
    """Refuse a domain and a problem that do not agree, before anything is planned.

    The domain's blocks-world predicates must have the blocks world's arities (``on`` two
    arguments, ...), and every atom of the problem (initial state and goal) must use a
    predicate the domain declares, with its arity: a 4-operator problem (``handempty``,
    ``ontable``) with the move domain is refused, not read as the other formulation.
    """
    declared = {p.name: p.arity for p in domain.predicates}
    for name, arity in sorted(declared.items()):
        canonical = PREDICATE_ALIASES.get(name)
        if canonical is not None and ARITY[canonical] != arity:
            raise PddlImportError(f"{domain_source}: declares {name} with {arity} argument(s); the blocks world's "
                                  f"{name} takes {ARITY[canonical]}")
    goal_pos, goal_neg = _goal_atoms(problem.goal, source)
    atoms = sorted([*(_atom(a, source, "initial state") for a in problem.init), *goal_pos, *goal_neg])
    unknown = sorted({name for name, _ in atoms if name not in declared})
    if unknown:
        used = ", ".join(f"({name})" for name in unknown[:4]) + (", ..." if len(unknown) > 4 else "")
        raise PddlImportError(f"{source}: uses {used}, which the domain {domain_source} does not declare; "
                              f"the problem and the domain are of different formulations")
    for name, args in atoms:
        if declared[name] != len(args):
            raise PddlImportError(f"{source}: ({' '.join([name, *args])}) has {len(args)} argument(s) but the domain "
                                  f"{domain_source} declares {name} with {declared[name]}")


def problem_from_pddl(problem, source: str, actions: frozenset[str] | None = None,  # noqa: ANN001
                      constants: tuple[str, ...] = (), max_blocks: int = MAX_LETTERS) -> BlocksProblem:
    """A :class:`BlocksProblem` from a parsed ``pddl`` Problem (see the module docstring for the rules)."""
    init = [_atom(a, source, "initial state") for a in problem.init]
    goal_pos, goal_neg = _goal_atoms(problem.goal, source)
    if any(CSQL_FACT.match(p) and not args for p, args in init + goal_pos + goal_neg):
        return _csql_problem(problem.name, init, goal_pos, goal_neg, source, actions)
    named = {o.name for o in problem.objects if o.type_tag != TABLE_NAME} | set(constants)
    for _, args in init:
        named.update(args)
    _check_goal_objects(goal_pos + goal_neg, named | {o.name for o in problem.objects}, source)
    declared = sorted(o.name for o in problem.objects if o.type_tag == TABLE_NAME)
    table = declared[0] if declared else TABLE_NAME if TABLE_NAME in named else None
    tables = {*declared, TABLE_NAME}
    objects = tuple(sorted(named - tables, key=name_key))
    _check_count(len(objects), source, objects, max_blocks)
    index = {**{name: i for i, name in enumerate(objects)}, **dict.fromkeys(tables, TABLE)}
    init_atoms = _canonical(init, index, source, "initial state")
    uses_hand = any(PREDICATE_ALIASES.get(p) in ("handempty", "holding") for p, _ in init + goal_pos + goal_neg)
    style = _style(actions) if actions is not None else "4op" if uses_hand else "move"
    uses_hand = uses_hand or style == "4op"
    start = _start_state(init_atoms, len(objects), source, objects, uses_hand)
    positive = _canonical(goal_pos, index, source, "goal")
    if style == "move":
        positive.add(("handempty", ()))
    goal = _goal(len(objects), positive, _canonical(goal_neg, index, source, "goal"), objects, source)
    return BlocksProblem(problem.name, objects, start, goal, style, actions, table)


def _check_goal_objects(goal: list[tuple[str, tuple[str, ...]]], known: set[str], source: str) -> None:
    """A goal may name only the problem's objects (declared, constants, or in the initial state)."""
    for name, args in goal:
        unknown = next((a for a in args if a not in known and a != TABLE_NAME), None)
        if unknown is not None:
            raise PddlImportError(f"{source}: the goal names an unknown object {unknown[:60]} in "
                                  f"({' '.join([name, *args])[:120]}); it is not among the problem's objects")


def _style(actions: frozenset[str]) -> str:
    if all(CSQL_ACTION.match(a) for a in actions):
        return "csql"
    return "4op" if all(a in DOMAIN_ACTIONS["4op"] for a in actions) else "move"


def _check_count(n: int, source: str, objects: tuple[str, ...], max_blocks: int = MAX_LETTERS) -> None:
    if n > max_blocks:
        more = " (letters A-Z; 'plan --problem' plans more)" if max_blocks == MAX_LETTERS else " for planning"
        raise PddlImportError(f"{source}: {n:,} blocks; csql-sim reads at most {max_blocks:,}{more}")
    if n < MIN_BLOCKS:
        raise PddlImportError(f"{source}: {n} block(s); csql-sim needs at least {MIN_BLOCKS}")


def _atom(formula, source: str, where: str) -> tuple[str, tuple[str, ...]]:  # noqa: ANN001
    from pddl.logic.predicates import Predicate

    if not isinstance(formula, Predicate):
        raise PddlImportError(f"{source}: {formula} in the {where} is not an atom; csql-sim takes atoms only")
    return formula.name, tuple(t.name for t in formula.terms)


def _goal_atoms(goal, source: str) -> tuple[list, list]:  # noqa: ANN001 - a pddl formula
    from pddl.logic.base import And, Not

    parts = goal.operands if isinstance(goal, And) else (goal,)
    pos, neg = [], []
    for part in parts:
        if isinstance(part, Not):
            neg.append(_atom(part.argument, source, "goal"))
        else:
            pos.append(_atom(part, source, "goal"))
    return pos, neg


def _canonical(atoms: list[tuple[str, tuple[str, ...]]], index: dict[str, int], source: str,
               where: str) -> set[Atom]:
    """Atoms over block indices; ``block`` tests and ``clear`` of the table are dropped."""
    out: set[Atom] = set()
    for name, args in atoms:
        pred = PREDICATE_ALIASES.get(name)
        text = "(" + " ".join([name, *args]) + ")"
        if pred is None:
            raise PddlImportError(f"{source}: unknown predicate {text} in the {where}; csql-sim knows on, ontable, "
                                  f"clear, handempty, holding")
        if ARITY[pred] != len(args):
            raise PddlImportError(f"{source}: {text} in the {where} takes {ARITY[pred]} argument(s)")
        ids = tuple(index[a] for a in args)
        if TABLE in ids[:1] and pred != "clear":
            raise PddlImportError(f"{source}: {text} in the {where} treats the table as a block")
        if pred == "block" or (pred == "clear" and ids[0] == TABLE):
            continue
        out.add(("on", (ids[0], TABLE)) if pred == "ontable" else (pred, ids))
    return out


def _start_state(atoms: set[Atom], n: int, source: str, objects: tuple[str, ...],
                 uses_hand: bool) -> State:
    """The one configuration the initial atoms describe, or a one-line refusal."""
    where: dict[int, list[int]] = {i: [] for i in range(n)}
    for pred, args in atoms:
        if pred in ("on", "holding"):
            where[args[0]].append(args[1] if pred == "on" else HAND)
    bad = next((i for i in range(n) if len(where[i]) != 1), None)
    if bad is not None:
        what = "is placed nowhere (no on, ontable or holding atom)" if not where[bad] else "is in two places"
        raise PddlImportError(f"{source}: the initial state is not a full configuration: {objects[bad]} {what}")
    try:
        support = tuple(where[i][0] for i in range(n))
        state = State(support, objects)  # its messages name the problem's objects
    except WorldError as exc:
        raise PddlImportError(f"{source}: the initial state is not a configuration ({exc})") from None
    if uses_hand and (("handempty", ()) in atoms) != (state.held is None):
        raise PddlImportError(f"{source}: the initial state says the hand is "
                              f"{'empty' if state.held is None else 'holding'} and the opposite")
    clear = {args[0] for pred, args in atoms if pred == "clear"}
    for i in range(n):
        if (i in clear) != state.is_clear(i):
            why = "has (clear {0}) but is not clear" if i in clear else "is clear but (clear {0}) is missing"
            raise PddlImportError(f"{source}: the initial state is not a full configuration: "
                                  f"{objects[i]} {why.format(objects[i])}")
    return state


def _goal(n: int, positive: set[Atom], negative: set[Atom], objects: tuple[str, ...], source: str) -> GoalSpec:
    try:
        return GoalSpec(n, frozenset(positive), frozenset(negative), names=objects)
    except GoalError as exc:
        raise PddlImportError(f"{source}: {exc}") from None


def _csql_problem(name: str, init: list, goal_pos: list, goal_neg: list, source: str,
                  actions: frozenset[str] | None) -> BlocksProblem:
    """A problem of csql-sim's own export: 0-ary facts named after the message's fields."""
    facts = [p for p, args in init + goal_pos + goal_neg if args or not CSQL_FACT.match(p)]
    if facts:
        raise PddlImportError(f"{source}: unknown predicate {facts[0]} beside csql-sim's message facts")
    letters = sorted({p.split("_")[1] for p, _ in init if p.startswith("on_")})
    _check_count(len(letters), source, tuple(letters))
    index = {**{c: i for i, c in enumerate(letters)}, "t": TABLE, "0": HAND}
    try:
        init_atoms = {_csql_atom(p, index) for p, _ in init}
        start = _start_state(init_atoms - {None}, len(letters), source, tuple(letters), True)
        positive = {_csql_atom(p, index) for p, _ in goal_pos} - {None}
        negative = {_csql_atom(p, index) for p, _ in goal_neg} - {None}
        negative |= {("clear", a) for p, a in positive if p == "not-clear"}
        positive = {a for a in positive if a[0] != "not-clear"}
    except KeyError as exc:
        raise PddlImportError(f"{source}: a fact names block {exc.args[0]!r}, which has no on_ fact") from None
    goal = _goal(len(letters), positive, negative, tuple(letters), source)
    return BlocksProblem(name, tuple(letters), start, goal, "csql", actions)


def _csql_atom(fact: str, index: dict[str, int]) -> Atom | None:
    """One message fact as an atom (``clear_x_0`` as the marker ``not-clear``; ``clear_x_1`` as clear)."""
    parts = fact.split("_")
    if parts[0] == "held":
        return ("handempty", ()) if parts[1] == "0" else ("holding", (index[parts[1]],))
    if parts[0] == "clear":
        return ("clear" if parts[2] == "1" else "not-clear", (index[parts[1]],))
    below = index[parts[2]]
    return ("holding", (index[parts[1]],)) if below == HAND else ("on", (index[parts[1]], below))
