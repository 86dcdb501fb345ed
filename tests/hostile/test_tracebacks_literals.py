"""Class 1 of issue 49: a generated-feature literal nested thousands deep, or cut short, is one line and exit 2.

Before the fix the feature grammar's recursive-descent parser ran into RecursionError on a
literal ``not(`` x 10,000 deep (500 deep was enough) and into IndexError on ``x:not(``, in
every reader of a committee file: ``plan``, ``show``, ``evaluate``, ``render``, ``execute``.
Now :func:`csql_sim.core.features.grammar.parse` bounds an expression's length and nesting
before it recurses, and reports an expression that ends early.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from hostile_cli import csql
from sweep4 import DEEP_40, DEEP_500, DEEP_LITERAL, TRUNCATED, committee, judged, problem, tower

from csql_sim.core.features.grammar import MAX_DEPTH, GrammarError, parse

READERS = {
    "show": ("show", "--rules", "r.json"),
    "plan-start-goal": ("plan", "--rules", "r.json", "--start", "CBA", "--goal", "ABC"),
    "plan-pairs": ("plan", "--rules", "r.json", "--blocks", 8, "--pairs", 3),
    "plan-out": ("plan", "--rules", "r.json", "--start", "GFEDCBA", "--goal", "ABCDEFG", "--plan-out", "x.plan"),
    "plan-problem": ("plan", "--problem", "p.pddl", "--rules", "r.json", "--optimum-budget", 0, "--plan-out", "o.plan"),
    "evaluate": ("evaluate", "--rules", "r.json", "--blocks", 7, "--pairs", 1),
    "render": ("render", "--rules", "r.json", "--start", "CBA", "--goal", "ABC", "--out", "v.gif"),
    "execute": ("execute", "--problem", "p.pddl", "--rules", "r.json", "--json", "rep.json"),
}


CASES = [(reader, DEEP_LITERAL) for reader in READERS] + [
    (reader, literal) for reader in ("show", "plan-problem") for literal in (DEEP_500, DEEP_40, TRUNCATED)]


@pytest.mark.parametrize(("reader", "literal"), CASES, ids=[f"{r}-{len(lit)}" for r, lit in CASES])
def test_a_hostile_literal_is_refused_by_every_reader(work: Path, reader: str, literal: str) -> None:
    """rs-r-lit-deep, rs-r-lit-trunc, rp-r-lit-deep(-500), rp-r-lit-trunc, rx-r-lit-deep-*, ex-objs7-lit-deep."""
    committee(work, "r.json", second=literal)
    names = [f"b{i}" for i in range(1, 8)]
    problem(work, "p.pddl", names, tower(names) + " (clear b7)", tower(names[::-1]))
    run = judged(work, lambda: csql(work, *READERS[reader], timeout=120))
    run.refused("r.json", "member 2")


def test_the_grammar_bounds_depth_and_length_and_reads_what_it_generates() -> None:
    with pytest.raises(GrammarError, match="ends early"):
        parse("not(")
    with pytest.raises(GrammarError, match="ends early"):
        parse("and(block,")
    with pytest.raises(GrammarError, match="deeper"):
        parse("not(" * (MAX_DEPTH + 1) + "block" + ")" * (MAX_DEPTH + 1))
    with pytest.raises(GrammarError, match="longer"):
        parse("and(" + "block," * 300 + "block)")
    deep = "not(" * MAX_DEPTH + "block" + ")" * MAX_DEPTH
    assert parse(deep).text() == deep  # the bound itself reads
    assert parse("all(star(on),eq(on,on_g))").complexity == 6
