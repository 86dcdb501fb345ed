"""Classes 3, 4, 6 and 7 of issue 49: wrong-domain plans, inputs replaced, links followed, misleading messages.

* A problem and its ``--domain`` that do not agree (a 4-operator problem with the move
  domain, a domain whose ``on`` takes three arguments) were planned anyway, exit 0; one
  check (``pddl_import.check_agreement``) now refuses them before planning.
* ``plan --problems DIR --json DIR/p.pddl --overwrite`` replaced an input problem, and
  ``train-lifted --out d.pddl --domain d.pddl --overwrite`` its input domain: every input
  named on the command line (a folder's problems too) is now an input of the output rule.
* A dangling link at ``--plan-out`` was followed without ``--overwrite``.
* A goal naming an unknown object blamed the initial state.
* A failed row quoted a 4,000-character token.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from hostile_cli import csql
from sweep4 import judged, problem, tower, tower_problem

ASSETS = Path(__file__).resolve().parents[2] / "assets" / "domains"
GN1 = ("--planner", "gn1", "--optimum-budget", 0)


def test_pp_good8_dommove(work: Path) -> None:
    tower_problem(work, "p.pddl", 8)
    (work / "d.pddl").write_bytes((ASSETS / "blocks-move.pddl").read_bytes())
    run = judged(work, lambda: csql(work, "plan", "--problem", "p.pddl", "--domain", "d.pddl", *GN1,
                                    "--plan-out", "out.plan"))
    run.refused("p.pddl", "d.pddl", "handempty")


def test_pp_dom_redef_on(work: Path) -> None:
    tower_problem(work, "p.pddl", 8)
    (work / "d.pddl").write_text((ASSETS / "blocks-4op.pddl").read_text().replace("(on ?x ?y)", "(on ?x ?y ?z)", 1))
    run = judged(work, lambda: csql(work, "plan", "--problem", "p.pddl", "--domain", "d.pddl", *GN1,
                                    "--plan-out", "out.plan"))
    run.refused("d.pddl", "on", "3")


def test_the_matching_domain_still_plans(work: Path) -> None:
    tower_problem(work, "p.pddl", 8)
    (work / "d.pddl").write_bytes((ASSETS / "blocks-4op.pddl").read_bytes())
    run = csql(work, "plan", "--problem", "p.pddl", "--domain", "d.pddl", *GN1, "--plan-out", "out.plan")
    assert run.returncode == 0 and run.stderr == "", run.stderr
    assert sum(line.startswith("(") for line in (work / "out.plan").read_text().splitlines()) == 16


@pytest.mark.parametrize("command", ["plan", "execute"])
def test_pp_goal_unknown_obj(work: Path, command: str) -> None:
    names = ["b1", "b2", "b3"]
    problem(work, "p.pddl", names, tower(names) + " (clear b3)", "(on b1 zz9)")
    tail = ("--plan-out", "out.plan") if command == "plan" else ("--json", "rep.json")
    run = judged(work, lambda: csql(work, command, "--problem", "p.pddl", "--planner", "gn1", *tail))
    err = run.refused("p.pddl", "goal", "unknown object zz9")
    assert "initial state" not in err


def test_pd_json_over_problem(work: Path) -> None:
    (work / "pr").mkdir()
    tower_problem(work / "pr", "good3.pddl", 3)
    run = judged(work, lambda: csql(work, "plan", "--problems", "pr", *GN1, "--json", "pr/good3.pddl",
                                    "--overwrite"))
    run.refused("pr/good3.pddl", "PDDL problem")


def test_tl_out_is_domain(work: Path) -> None:
    (work / "d.pddl").write_bytes((ASSETS / "blocks-move.pddl").read_bytes())
    run = judged(work, lambda: csql(work, "train-lifted", "--out", "d.pddl", "--features", "generated", "--trials", 2,
                                    "--committee", 1, "--complexity", 2, "--domain", "d.pddl", "--overwrite"))
    run.refused("d.pddl", "PDDL domain")


def test_po_dangling_symlink(work: Path) -> None:
    tower_problem(work, "p.pddl", 4)
    (work / "link.plan").symlink_to("nowhere/x.plan")
    run = judged(work, lambda: csql(work, "plan", "--problem", "p.pddl", *GN1, "--plan-out", "link.plan"))
    run.refused("link.plan")
    assert not (work / "nowhere").exists()


def test_pd_mixed_row_quotes_a_short_token(work: Path) -> None:
    (work / "pr").mkdir()
    tower_problem(work / "pr", "good3.pddl", 3)
    (work / "pr" / "tok.pddl").write_text("(define (problem a) (:domain b) " + "x" * 4000 + ")")
    run = csql(work, "plan", "--problems", "pr", *GN1, "--json")
    assert run.returncode == 1 and run.stderr == "", run.stderr
    rows = {Path(r["problem"]).name: r for r in json.loads(run.stdout)["rows"]}
    assert rows["good3.pddl"]["solved"] and not rows["tok.pddl"]["solved"]
    assert "tok.pddl" in rows["tok.pddl"]["reason"] and len(rows["tok.pddl"]["reason"]) < 300
