"""The plan validator's verdicts agree with unified-planning's on valid plans and on mutated ones."""

import re
from pathlib import Path

import numpy as np
import pytest

from csql_sim.core.files.validate import validate_plan_file
from csql_sim.core.policies.loader import load_policy
from csql_sim.infra.assets import builtin_rules_path
from csql_sim.infra.errors import CsqlError
from csql_sim.jobs.plan_problems import plan_problem
from csql_sim.jobs.problems import drawn_problems


def shipped(n):
    """The shipped lifted rules (``--rules builtin``), the planner whose plans are checked."""
    return load_policy(builtin_rules_path(), n)


up = pytest.importorskip("unified_planning", reason="unified-planning is in the test extra: pip install '.[test]'")

WORDS = ("amber", "pearl", "onyx", "jade", "ruby", "opal", "coral", "ivory", "slate", "umber", "topaz", "beryl")
MOVE_DOMAIN = """(define (domain blocksworld)
  (:requirements :strips :equality :negative-preconditions)
  (:predicates (clear ?x) (on-table ?x) (on ?x ?y))
  (:action move-b-to-b :parameters (?bm ?bf ?bt)
    :precondition (and (clear ?bm) (clear ?bt) (on ?bm ?bf) (not (= ?bm ?bt)))
    :effect (and (not (clear ?bt)) (not (on ?bm ?bf)) (on ?bm ?bt) (clear ?bf)))
  (:action move-b-to-t :parameters (?bm ?bf)
    :precondition (and (clear ?bm) (on ?bm ?bf))
    :effect (and (not (on ?bm ?bf)) (on-table ?bm) (clear ?bf)))
  (:action move-t-to-b :parameters (?bm ?bt)
    :precondition (and (clear ?bm) (clear ?bt) (on-table ?bm) (not (= ?bm ?bt)))
    :effect (and (not (clear ?bt)) (not (on-table ?bm)) (on ?bm ?bt))))
"""


def named_task(tmp_path: Path, n: int, seed: int, move: bool) -> tuple[Path, Path, list[str]]:
    """A drawn problem whose objects b1..bN are renamed to words; its domain, its file and the names."""
    (_, domain_text), (name, text) = drawn_problems("tall-towers", [n], 1, seed=seed)
    names = [WORDS[i] for i in range(n)]
    text = re.sub(r"\bb(\d+)\b", lambda m: names[int(m.group(1)) - 1], text)
    if move:
        domain_text = MOVE_DOMAIN
        text = text.replace("(handempty)", "").replace("ontable", "on-table").replace("(:domain blocks)",
                                                                                          "(:domain blocksworld)")
    domain, problem = tmp_path / "domain.pddl", tmp_path / name
    domain.write_text(domain_text)
    problem.write_text(text)
    return domain, problem, names


def up_task(domain: Path, problem: Path):  # noqa: ANN201 - a unified-planning Problem
    """The problem as unified-planning reads it."""
    from unified_planning.io import PDDLReader
    from unified_planning.shortcuts import get_environment

    get_environment().credits_stream = None
    return PDDLReader().parse_problem(str(domain), str(problem))


def up_verdict(task, lines: list[str]) -> bool:  # noqa: ANN001 - a unified-planning Problem
    """unified-planning's verdict on the plan ``lines`` (True: valid)."""
    from unified_planning.engines import ValidationResultStatus
    from unified_planning.plans import ActionInstance, SequentialPlan
    from unified_planning.shortcuts import PlanValidator

    steps = []
    for line in lines:
        word, *args = line.strip("()").split()
        steps.append(ActionInstance(task.action(word), [task.object(a) for a in args]))
    with PlanValidator(name="sequential_plan_validator") as validator:
        return validator.validate(task, SequentialPlan(steps)).status == ValidationResultStatus.VALID


def mutations(lines: list[str], names: list[str], rng: np.random.Generator) -> list[list[str]]:
    """A dropped step, two swapped steps and a wrong object, at seeded places."""
    out = []
    k = int(rng.integers(len(lines)))
    out.append(lines[:k] + lines[k + 1:])
    k = int(rng.integers(len(lines) - 1))
    out.append(lines[:k] + [lines[k + 1], lines[k]] + lines[k + 2:])
    k = int(rng.integers(len(lines)))
    word, *args = lines[k].strip("()").split()
    slot = int(rng.integers(len(args)))
    others = [x for x in names if x not in args]
    args[slot] = others[int(rng.integers(len(others)))]
    out.append(lines[:k] + [f"({' '.join([word, *args])})"] + lines[k + 1:])
    return out


@pytest.mark.parametrize("move", [False, True], ids=["4op", "move"])
@pytest.mark.parametrize("seed", [1, 2])
def test_verdicts_agree_with_unified_planning_on_valid_and_mutated_plans(tmp_path, move, seed):
    domain, problem, names = named_task(tmp_path, 9, seed, move)
    planned = plan_problem(problem, domain, shipped, "rules", 0.0)
    assert planned.solved and any(name in planned.lines[0] for name in names)
    rng = np.random.default_rng(seed)
    plans = [list(planned.lines), *mutations(list(planned.lines), names, rng)]
    task, verdicts = up_task(domain, problem), []
    for i, lines in enumerate(plans):
        path = tmp_path / f"plan{i}.plan"
        path.write_text("".join(line + "\n" for line in lines))
        ours = validate_plan_file(problem, path, domain)
        assert ours.valid == up_verdict(task, lines), lines
        assert ours.valid == (not ours.errors)
        verdicts.append(ours.valid)
    assert verdicts[0] and verdicts[1] is False  # the plan is valid; without one of its steps it is not


def test_a_failing_step_is_named_with_its_precondition(tmp_path):
    domain, problem, names = named_task(tmp_path, 9, 5, move=False)
    planned = plan_problem(problem, domain, shipped, "rules", 0.0)
    lines = list(planned.lines)
    path = tmp_path / "p.plan"
    path.write_text("; a comment line\n" + "\n".join(lines[:2] + lines[3:]) + "\n")  # step 3 dropped
    verdict = validate_plan_file(problem, path, domain)
    (error,) = verdict.errors
    assert not verdict.valid and verdict.applied == 2
    assert error.startswith(f"step 3 (line 4) {lines[3]}: precondition (")
    assert re.search(r"[A-Z]", error.split(": precondition")[0].replace(lines[3], "")) is None  # no cube letters


def test_a_plan_that_stops_short_names_each_goal_atom_missed(tmp_path):
    domain, problem, _ = named_task(tmp_path, 9, 6, move=False)
    planned = plan_problem(problem, domain, shipped, "rules", 0.0)
    path = tmp_path / "p.plan"
    path.write_text("")
    verdict = validate_plan_file(problem, path, domain)
    assert not verdict.valid and verdict.steps == 0 and verdict.errors
    assert all(e.startswith("goal (") and e.endswith("does not hold after step 0") for e in verdict.errors)
    assert not up_verdict(up_task(domain, problem), []) and planned.solved


def test_a_plan_naming_an_unknown_object_is_bad_input(tmp_path):
    domain, problem, _ = named_task(tmp_path, 9, 7, move=False)
    path = tmp_path / "p.plan"
    path.write_text("(unstack amber zircon)\n")
    with pytest.raises(CsqlError, match="line 1: unknown object 'zircon'"):
        validate_plan_file(problem, path, domain)
