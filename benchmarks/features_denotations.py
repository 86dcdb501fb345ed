"""Denotations of a planning batch: the planner's shortcuts against the definitions, timed in one run.

Regenerates docs/results/features.md, planning speed (the denotations' shortcuts against the definitions).

    python benchmarks/features_denotations.py [--rules FILE] [--domain move] [--blocks 100] [--table 40] [--repeat 3]

The batch is what a greedy policy over generated features evaluates at one step: a state and
the state after each of its legal moves, towards one goal. The state is the first tall-tower
task of ``--blocks`` blocks (``csql-sim problems --distribution tall-towers``, seed 0) with
the tops of its towers put on the table ``--table`` times; the goal is that task's. The
concepts are those the literals of ``--rules`` read (every member of a committee), or else
every concept the grammar generates within complexity 6 on sampled four-block pairs of
``--domain``. Both sides remember sub-expressions within the batch:

* shortcuts: :class:`csql_sim.core.features.denotation.Denotations`, the goal given once;
* definitions: :func:`csql_sim.core.features.denotation.by_definition`, the goal in every row;
* definitions member by member: the same, each member of a committee on its own batch (as
  before members shared one).

It prints the seconds of each (the median of ``--repeat``), their ratio, and whether every
concept's denotation is the same.
"""

from __future__ import annotations

import argparse
import json
import statistics
import time

import numpy as np

from csql_sim.core.features.denotation import Denotations, by_definition
from csql_sim.core.features.formulation import load_formulation, parse_formulation, primitive_arrays, support_arrays
from csql_sim.core.features.generate import generate_concepts
from csql_sim.core.features.move_features import parse_literal, parsed
from csql_sim.core.model.task_draws import draw_task
from csql_sim.core.state.move_relations import towards
from csql_sim.core.state.moves import after, moves
from csql_sim.core.state.state_count import sample_pairs
from csql_sim.core.state.world import TABLE, State


def batch(blocks: int, table: int) -> tuple[list[State], State]:
    """The state after ``table`` tops went to the table, each state after one of its moves, and the target."""
    start, goal = draw_task("tall-towers", blocks, np.random.default_rng(0))
    sup = list(start.support)
    for _ in range(table):
        state = State(tuple(sup))
        tops = [b for b in range(blocks) if state.is_clear(b) and sup[b] != TABLE]
        if not tops:
            break
        sup[tops[0]] = TABLE
    state = State(tuple(sup))
    target = towards(state, goal)[0] or goal
    return [state] + [after(state, m) for m in moves(state)], target


def concepts(rules: str | None, domain: str):  # noqa: ANN201 - the formulation and each member's nodes
    """The formulation and the concepts measured, member by member (one member without a committee)."""
    if rules:
        with open(rules, encoding="utf-8") as f:
            doc = json.load(f)
        form = parse_formulation(doc["domain"], rules, doc.get("formulation") or "domain")
        members = [[parse_literal(a) for a in m["atoms"]] for m in doc.get("members", [doc])]
        return form, [list(dict.fromkeys(parsed(lit.feature) for lit in m if lit.slot != "holds")) for m in members]
    form = load_formulation(domain)
    small = sample_pairs(4, 60, np.random.default_rng(0))
    prims, objects = primitive_arrays(form, [s for s, _ in small], [g for _, g in small])
    return form, [list(generate_concepts(form, Denotations(prims, objects, form.constants), 6).concepts)]


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--rules", help="a generated-features or committee file whose literals' concepts are measured")
    p.add_argument("--domain", default="move", help="without --rules: the formulation (default move)")
    p.add_argument("--blocks", type=int, default=100)
    p.add_argument("--table", type=int, default=40)
    p.add_argument("--repeat", type=int, default=3)
    args = p.parse_args()
    form, members = concepts(args.rules, args.domain)
    nodes = list(dict.fromkeys(c for m in members for c in m))
    states, target = batch(args.blocks, args.table)
    sup = np.array([s.support for s in states], np.int64)
    goal = np.array([target.support], np.int64)
    times: dict[str, list[float]] = {"shortcuts": [], "definitions": [], "apart": []}
    same = True
    for _ in range(args.repeat):
        t0 = time.perf_counter()
        compact, objects = support_arrays(form, sup, goal)
        den = Denotations(compact, objects, form.constants)
        fast = [den.of(c) for c in nodes]
        t1 = time.perf_counter()
        full, _ = support_arrays(form, sup, np.repeat(goal, len(sup), axis=0))
        memo: dict = {}
        slow = [by_definition(c, full, objects, form.constants, memo) for c in nodes]
        t2 = time.perf_counter()
        for member in members:  # each member its own batch, as a committee planned before it shared one
            full, _ = support_arrays(form, sup, np.repeat(goal, len(sup), axis=0))
            memo = {}
            for c in member:
                by_definition(c, full, objects, form.constants, memo)
        t3 = time.perf_counter()
        for key, seconds in zip(times, (t1 - t0, t2 - t1, t3 - t2), strict=True):
            times[key].append(seconds)
        same = same and all((a == b).all() for a, b in zip(fast, slow, strict=True))
    f, s, a = (statistics.median(times[k]) for k in times)
    print(f"{len(states) - 1} moves of {args.blocks} blocks, {len(members)} member(s), {len(nodes)} concepts: "
          f"shortcuts {f:.3f} s; definitions {s:.3f} s (ratio {s / f:.1f}); definitions member by member "
          f"{a:.3f} s (ratio {a / f:.1f}); the same denotations: {'yes' if same else 'NO'}")


if __name__ == "__main__":
    main()
