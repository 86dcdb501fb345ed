"""Fixtures of the fourth hostile sweep (issue 49, ``../shared/hostile-cases-2026-12-01.md``), built in tmp.

``committee(work, name, second=...)`` writes a two-member committee file of the move domain
(the member literals replaced by ``atoms``); ``tower_problem(work, name, n)`` a problem whose
single tower of ``n`` blocks is rebuilt upside down; ``problem(work, name, init, goal)`` any
problem over objects ``b1..bn``. ``judged(work, run_it, outputs)`` runs a command and asserts
nothing but ``outputs`` changed in ``work``.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

from hostile_cli import Run, digest

from csql_sim.core.features.move_features import Literal
from csql_sim.core.policies.committee_policy import dumps_committee
from csql_sim.core.policies.lifted_classifier import LiftedQClassifier
from csql_sim.infra.assets import asset_text

WELL_PLACED = "all(star(on),eq(on,on_g))"
DEEP_LITERAL = "x:" + "not(" * 10_000 + "block" + ")" * 10_000
DEEP_500 = "x:" + "not(" * 500 + "block" + ")" * 500
DEEP_40 = "x:" + "not(" * 40 + "block" + ")" * 40
TRUNCATED = "x:not("


def committee(work: Path, name: str, second: str | None = None, formulation: str = "move") -> str:
    """A committee of two constructive members; ``second`` replaces member 2's literal."""
    classifiers = [LiftedQClassifier("1", "block", 0.0), LiftedQClassifier("0", "block", 2.0),
                   LiftedQClassifier("#", "table", 1.0)]
    literals = (Literal(WELL_PLACED, "x'"),)
    doc = json.loads(dumps_committee([(classifiers, literals)] * 2, asset_text("domains", "blocks-move.pddl"),
                                     "move", {}))
    doc["formulation"] = formulation
    if second is not None:
        doc["members"][1]["atoms"] = [second]
    (work / name).write_text(json.dumps(doc), encoding="utf-8")
    return name


def problem(work: Path, name: str, objects: list[str], init: str, goal: str, hand: bool = True) -> str:
    """A 4-operator problem file (``(handempty)`` added to ``init`` unless ``hand`` is false)."""
    text = (f"(define (problem {Path(name).stem})\n  (:domain blocks)\n  (:objects {' '.join(objects)})\n"
            f"  (:init {'(handempty) ' if hand else ''}{init})\n  (:goal (and {goal})))\n")
    (work / name).write_text(text, encoding="utf-8")
    return name


def tower(names: list[str]) -> str:
    """The atoms of one tower, ``names[0]`` on the table, each next one on the one before, the top clear."""
    atoms = [f"(ontable {names[0]})"] + [f"(on {b} {a})" for a, b in zip(names, names[1:], strict=False)]
    return " ".join(atoms)


def tower_problem(work: Path, name: str, n: int) -> str:
    """One tower b1 (bottom) .. bn, to be rebuilt upside down: bn on the table, b1 on top."""
    names = [f"b{i}" for i in range(1, n + 1)]
    init = tower(names) + f" (clear {names[-1]})"
    return problem(work, name, names, init, tower(names[::-1]))


def judged(work: Path, run_it: Callable[[], Run], outputs: tuple[str, ...] = ()) -> Run:
    """Run a command and assert no entry of ``work`` but ``outputs`` appeared, vanished or changed."""
    before = digest(work)
    run = run_it()
    after = digest(work)
    changed = {k for k in before.keys() | after.keys() if before.get(k) != after.get(k)}
    assert changed <= set(outputs), sorted(changed)
    return run


def replay_4op(plan_text: str, names: list[str]) -> dict[str, str]:
    """Apply a 4-operator plan to the tower ``names`` (bottom first); the supports it ends with (block -> below).

    An action that is not applicable fails the assertion: this is the test's own simulator.
    """
    below = {names[0]: "table", **{b: a for a, b in zip(names, names[1:], strict=False)}}
    held = None

    def clear(x: str) -> bool:
        return x != held and x not in below.values()

    for line in plan_text.splitlines():
        if not line.strip() or line.startswith(";"):
            continue
        op, *args = line.strip("()\n ").split()
        x = args[0]
        if op in ("pick-up", "unstack"):
            assert held is None and clear(x) and below[x] == ("table" if op == "pick-up" else args[1]), line
            held = x
            del below[x]
        else:
            assert held == x and (op == "put-down" or clear(args[1])), line
            below[x], held = ("table" if op == "put-down" else args[1]), None
    assert held is None
    return below
