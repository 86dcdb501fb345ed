"""Random blocks-world problems in the IPC format, with BFS plans for the ones the arm can run.

:func:`generate_problem` draws a start and a goal configuration of ``n`` objects named
``a``, ``b``, ... and writes them as a problem of the IPC 2000 blocks domain
(:data:`DOMAIN_TEXT`: ``pick-up``, ``put-down``, ``stack``, ``unstack``). Each
configuration is drawn by taking the objects in a random order and putting each one
either on the table or on top of one of the towers built so far, all of these choices
equally likely: the **sequential** draw (simple and reproducible; it is not uniform over
configurations: :func:`drawn_problems` draws uniformly, or tall towers). The hand is
empty in both. The goal lists ``(on x y)`` for every stacked object and ``(ontable x)``
for every bottom one, so it is one state.

:func:`write_problem_set` writes ``domain.pddl``, the problems and, for at most six
blocks, the optimal plan of each (:func:`~csql_sim.core.model.search.bfs_plan`, written as Fast
Downward does by :func:`~csql_sim.core.files.ipc_plan.write_ipc_plan`). ``n`` may be 3..10;
problems of more than six blocks are written, and ``execute`` refuses them today.

:func:`drawn_problems` (``csql-sim problems``) draws tasks of up to 1,000 blocks named
``b1 ... bN`` from a named distribution (:mod:`csql_sim.core.model.task_draws`:
``tall-towers`` or ``uniform``), seeded and byte-identical per seed.
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from csql_sim.core.files.ipc_plan import ipc_plan_text
from csql_sim.core.model.search import bfs_plan
from csql_sim.core.model.task_draws import check_max_height
from csql_sim.core.model.task_draws import draw_task as draw_relational
from csql_sim.core.state.state import default_names
from csql_sim.core.state.world import MAX_BLOCKS, TABLE, State, WorldError
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import write_or_keep

MIN_OBJECTS, MAX_OBJECTS = 3, 10
NAMES = "abcdefghij"
DOMAIN_TEXT = """\
(define (domain blocks)
  (:requirements :strips)
  (:predicates (on ?x ?y) (ontable ?x) (clear ?x) (handempty) (holding ?x))
  (:action pick-up
    :parameters (?x)
    :precondition (and (clear ?x) (ontable ?x) (handempty))
    :effect (and (not (ontable ?x)) (not (clear ?x)) (not (handempty)) (holding ?x)))
  (:action put-down
    :parameters (?x)
    :precondition (holding ?x)
    :effect (and (not (holding ?x)) (clear ?x) (handempty) (ontable ?x)))
  (:action stack
    :parameters (?x ?y)
    :precondition (and (holding ?x) (clear ?y))
    :effect (and (not (holding ?x)) (not (clear ?y)) (clear ?x) (handempty) (on ?x ?y)))
  (:action unstack
    :parameters (?x ?y)
    :precondition (and (on ?x ?y) (clear ?x) (handempty))
    :effect (and (holding ?x) (clear ?y) (not (clear ?x)) (not (handempty)) (not (on ?x ?y)))))
"""
"""The 4-operator blocks domain of IPC 2000 (the paper's actions)."""

Towers = list[list[int]]


def random_towers(n: int, rng: np.random.Generator) -> Towers:
    """Towers (bottom up, object indices) built by placing the objects in a random order (module docstring)."""
    towers: Towers = []
    for obj in rng.permutation(n).tolist():
        choice = int(rng.integers(len(towers) + 1))
        if choice == len(towers):
            towers.append([obj])
        else:
            towers[choice].append(obj)
    return towers


def towers_of(state: State) -> Towers:
    """A hand-empty state's towers, bottom up."""
    if state.held is not None:
        raise CsqlError(f"{state.notation()} holds a block; IPC problems here start and end with an empty hand")
    return [list(t) for t in state.towers()]


def _atoms(towers: Towers, names: str) -> list[str]:
    out = []
    for tower in towers:
        out.append(f"(ontable {names[tower[0]]})")
        out += [f"(on {names[up]} {names[down]})" for down, up in zip(tower, tower[1:], strict=False)]
    return out


def problem_text(name: str, n: int, start: Towers, goal: Towers, names: str | list[str] = NAMES) -> str:
    """An IPC problem of the 4-operator domain: ``start`` and ``goal`` as towers of object indices."""
    init = ["(handempty)", *_atoms(start, names), *(f"(clear {names[t[-1]]})" for t in start)]
    return (f"(define (problem {name})\n  (:domain blocks)\n  (:objects {' '.join(names[:n])})\n"
            f"  (:init {' '.join(init)})\n  (:goal (and {' '.join(_atoms(goal, names))})))\n")


def task_problem_text(start: State, goal: State, name: str = "task") -> str:
    """A csql-sim task (hand-empty start and goal) as an IPC problem; cube A is object ``a`` (AA ``aa``)."""
    names = [x.lower() for x in default_names(start.n)]
    return problem_text(name, start.n, towers_of(start), towers_of(goal), names)


def draw_task(n: int, rng: np.random.Generator) -> tuple[Towers, Towers]:
    """A random start and goal of ``n`` (3..10) objects, drawn in that order."""
    if not MIN_OBJECTS <= n <= MAX_OBJECTS:
        raise CsqlError(f"problems have {MIN_OBJECTS}..{MAX_OBJECTS} objects, got {n}")
    return random_towers(n, rng), random_towers(n, rng)


def generate_problem(n: int, rng: np.random.Generator, name: str | None = None) -> str:
    """A random problem of ``n`` (3..10) objects as IPC text (see the module docstring)."""
    start, goal = draw_task(n, rng)
    return problem_text(name or f"blocks{n}", n, start, goal)


def state_of(towers: Towers, n: int) -> State:
    """The hand-empty state of towers of object indices (n at most six)."""
    support = [TABLE] * n
    for tower in towers:
        for down, up in zip(tower, tower[1:], strict=False):
            support[up] = down
    return State(tuple(support))


def write_problem_set(out: str | os.PathLike, count: int, blocks: list[int], seed: int = 0,
                      plans: bool = True) -> list[Path]:
    """Write ``domain.pddl`` and ``count`` problems per size in ``blocks`` (and BFS plans for n <= 6).

    Problems are named ``blocks<n>-<k>.pddl`` (k from 01), plans ``blocks<n>-<k>.plan``; one
    generator seeded with ``seed`` draws them all, size by size in the order given.
    """
    if count < 1:
        raise CsqlError(f"count must be at least 1, got {count}")
    rng = np.random.default_rng(seed)
    folder = Path(out)
    files: list[tuple[Path, str]] = [(folder / "domain.pddl", DOMAIN_TEXT)]
    for n in blocks:
        for k in range(1, count + 1):
            name = f"blocks{n}-{k:02d}"
            start, goal = draw_task(n, rng)
            files.append((folder / f"{name}.pddl", problem_text(name, n, start, goal)))
            if plans and n <= MAX_BLOCKS:
                files.append((folder / f"{name}.plan", ipc_plan_text(bfs_plan(state_of(start, n), state_of(goal, n)))))
    folder.mkdir(parents=True, exist_ok=True)
    return write_or_keep(files)


# ---------------------------------------------------------------- drawn tasks of up to 1,000 blocks


def block_names(n: int) -> list[str]:
    """``b1 ... bN``: the object names of drawn problems."""
    return [f"b{i + 1}" for i in range(n)]


def relational_problem_text(name: str, start: State, goal: State) -> str:
    """A hand-empty relational task as an IPC problem with objects ``b1 ... bN``."""
    return problem_text(name, start.n, [list(t) for t in start.towers()], [list(t) for t in goal.towers()],
                        block_names(start.n))


MAX_DRAWN_PROBLEMS = 10_000
"""The most problems one ``problems`` run writes (all sizes together), checked before anything is drawn."""


def drawn_names(distribution: str, blocks: list[int], count: int, max_height: int | None = None) -> list[str]:
    """The file names :func:`iter_drawn_problems` gives, without drawing: ``domain.pddl``, then the problems.

    Raises:
        CsqlError: ``count`` below 1, more than :data:`MAX_DRAWN_PROBLEMS` problems in all, or a
            ``max_height`` the draw cannot meet (:func:`csql_sim.core.model.task_draws.check_max_height`).
    """
    if count < 1:
        raise CsqlError(f"count must be at least 1, got {count}")
    for n in blocks:
        try:
            check_max_height(distribution, n, max_height)
        except WorldError as exc:
            raise CsqlError(str(exc)) from None
    if count * len(blocks) > MAX_DRAWN_PROBLEMS:
        raise CsqlError(f"{count} problems for each of {len(blocks)} size(s) is {count * len(blocks):,} problems; "
                        f"one run writes at most {MAX_DRAWN_PROBLEMS:,}")
    return ["domain.pddl", *(f"{distribution}-{n}-{k:02d}.pddl" for n in blocks for k in range(1, count + 1))]


def iter_drawn_problems(distribution: str, blocks: list[int], count: int, seed: int = 0,
                        max_height: int | None = None) -> Iterator[tuple[str, str]]:
    """``(file name, text)`` of ``domain.pddl`` and ``count`` problems per size, each drawn when asked for.

    Problems are named ``<distribution>-<n>-<k>.pddl`` (k from 01); one generator seeded
    with ``seed`` draws them all, size by size in the order given, start before goal;
    ``max_height``: only tasks whose towers are at most that high (rejection sampling).
    """
    drawn_names(distribution, blocks, count, max_height)  # the bounds, before the first draw
    rng = np.random.default_rng(seed)
    yield "domain.pddl", DOMAIN_TEXT
    for n in blocks:
        for k in range(1, count + 1):
            name = f"{distribution}-{n}-{k:02d}"
            try:
                start, goal = draw_relational(distribution, n, rng, max_height)
            except WorldError as exc:
                raise CsqlError(str(exc)) from None
            limit = "" if max_height is None else f", towers at most {max_height} high"
            header = f"; csql-sim problem: {distribution}, {n} blocks{limit}, seed {seed}, task {k}\n"
            yield f"{name}.pddl", header + relational_problem_text(name, start, goal)


def drawn_problems(distribution: str, blocks: list[int], count: int, seed: int = 0,
                   max_height: int | None = None) -> list[tuple[str, str]]:
    """:func:`iter_drawn_problems` as a list."""
    return list(iter_drawn_problems(distribution, blocks, count, seed, max_height))
