"""``plan`` and ``validate``: a blocks-world PDDL problem, from a path or its text, to a plan and a verdict.

A problem (and a domain) is a path or the PDDL text itself (:func:`read_blocks`). The
default planner is the shipped lifted rules (``rules="builtin"``, the file
``assets/rules/lifted.json``), which plan up to
:data:`~csql_sim.core.files.pddl_import.MAX_PLANNED_BLOCKS` objects; a rule file from
``csql-sim train-lifted``, ``planner="bfs"`` (up to six blocks) or ``planner="gn1"`` (the
baseline) plan instead when asked. The work is :func:`csql_sim.jobs.plan_problems.plan_problem`.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence

from csql_sim.api.results import ActionTuple, LiftedRules, Plan, Validation, action_line, action_tuple
from csql_sim.core.files.ipc_plan import PlanError, check_plan, parse_plan
from csql_sim.core.files.pddl_import import (
    MAX_PDDL_BYTES,
    MAX_PLANNED_BLOCKS,
    BlocksProblem,
    parse_problem_text,
    read_problem,
)
from csql_sim.core.policies.contract import Policy
from csql_sim.infra.assets import asset_text
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import read_text_file
from csql_sim.jobs.plan_problems import plan_problem

Source = str | os.PathLike
"""A path, or (a string holding a parenthesis) the text itself."""
PlanSource = Source | Sequence[str] | Sequence[ActionTuple] | Plan
"""A plan: a plan file, its text, a list of lines ``"(unstack a b)"`` or tuples ``("unstack", "a", "b")``, a Plan."""
BUILTIN = "builtin"
"""The name of the shipped lifted rules (``rules="builtin"``)."""
PLANNERS = ("builtin", "rules", "bfs", "gn1")


def is_text(source: object) -> bool:
    """Whether ``source`` is PDDL (or plan) text rather than a path: a string with a parenthesis."""
    return isinstance(source, str) and "(" in source


def read_blocks(problem: Source, domain: Source | None = None, max_blocks: int = MAX_PLANNED_BLOCKS) -> BlocksProblem:
    """A blocks-world problem from a path or PDDL text (its domain likewise, optional)."""
    if not is_text(problem) and not is_text(domain):
        return read_problem(problem, domain, max_blocks=max_blocks)
    text = problem if is_text(problem) else read_text_file(problem, MAX_PDDL_BYTES, "PDDL problem")
    domain_text = None if domain is None else domain if is_text(domain) else \
        read_text_file(domain, MAX_PDDL_BYTES, "PDDL domain")
    source = "problem" if is_text(problem) else os.fspath(problem)
    return parse_problem_text(text, source, domain_text, max_blocks=max_blocks)


def builtin_policy() -> Policy:
    """The shipped lifted rules (any number of blocks)."""
    from csql_sim.core.policies.committee_policy import loads_lifted_file

    return loads_lifted_file(asset_text("rules", "lifted.json"), "the built-in lifted rules")


def planner_of(rules: Source | LiftedRules | None, planner: str | None) -> str:
    """Who plans, from ``rules`` and ``planner`` (see :func:`plan`); a CsqlError for a contradiction."""
    if planner is not None and planner not in PLANNERS:
        raise CsqlError(f"planner must be one of {', '.join(PLANNERS)}, got {planner!r}")
    if planner is None:
        return BUILTIN if rules is None or rules == BUILTIN else "rules"
    if planner == "rules" and rules is None:
        raise CsqlError("planner 'rules' needs rules (a rule file or 'builtin')")
    if planner in ("bfs", "gn1") and rules is not None:
        raise CsqlError(f"planner {planner!r} reads no rules; give rules or the planner, not both")
    return BUILTIN if planner == "rules" and rules == BUILTIN else planner


def policy_maker(rules: Source | LiftedRules | None, planner: str, progress: bool = False) -> Callable[[int], Policy]:
    """The planner's policy for a problem of n blocks (loaded once; CsqlError where it cannot plan n)."""
    from csql_sim.core.policies.committee_policy import loads_lifted_file
    from csql_sim.core.policies.gn1 import Gn1Policy
    from csql_sim.core.policies.loader import load_policy

    cache: dict[int, Policy] = {}

    def make(n: int) -> Policy:
        if n not in cache:
            if planner == BUILTIN:
                cache[n] = builtin_policy()
            elif isinstance(rules, LiftedRules):
                cache[n] = loads_lifted_file(rules.text, "the rules of train_lifted")
            elif planner == "gn1":
                cache[n] = Gn1Policy()
            else:
                cache[n] = load_policy(rules if planner == "rules" else None, n, progress=progress)
        return cache[n]

    return make


def plan(problem: Source, domain: Source | None = None, rules: Source | LiftedRules | None = None,
         planner: str | None = None, optimum_budget: float = 0.0, progress: bool = False) -> Plan:
    """Plan a blocks-world PDDL problem, in its own names.

    Args:
        problem: the problem file, or its PDDL text.
        domain: its domain file or text (optional: the problem's predicates decide).
        rules: a rule file (lifted rules plan any n; ground ones up to six blocks), the rules
            :func:`~csql_sim.api.running.train_lifted` returned, or ``"builtin"`` (the default: the
            shipped lifted rules).
        planner: ``"builtin"``, ``"rules"`` (``rules``), ``"bfs"`` (optimal, up to six blocks)
            or ``"gn1"`` (the GN1 baseline); default: ``rules``, else the built-in rules.
        optimum_budget: seconds to bound the optimum past six blocks (0: not measured); up to six
            blocks the optimum is exact by breadth-first search.
        progress: a bar on stderr while a large rule file is read.

    Raises:
        CsqlError: one line for an unreadable problem or a planner that cannot plan it.

    Example:
        >>> import csql_sim
        >>> p = csql_sim.plan('''(define (problem two) (:domain blocks) (:objects amber pearl)
        ...   (:init (handempty) (on amber pearl) (ontable pearl) (clear amber))
        ...   (:goal (on pearl amber)))''')
        >>> p.actions
        (('unstack', 'amber', 'pearl'), ('put-down', 'amber'), ('pick-up', 'pearl'), ('stack', 'pearl', 'amber'))
        >>> p.solved, p.length, p.optimal_length
        (True, 4, 4)
    """
    chosen = planner_of(rules, planner)
    blocks = read_blocks(problem, domain)
    report = plan_problem(_shown(problem), domain, policy_maker(rules, chosen, progress), chosen, optimum_budget,
                          blocks=blocks)
    optimum = report.optimum
    return Plan(problem=blocks.name, objects=blocks.names, actions=tuple(action_tuple(x) for x in report.lines),
                solved=report.solved, planner=chosen,
                optimal_length=optimum.lower if optimum is not None and optimum.proven else None,
                lower_bound=report.lower_bound, reason=report.reason, seconds=report.seconds, report=report)


def _shown(source: Source) -> str:
    """How a problem is named in a report: its path, or ``problem`` for a text."""
    return "problem" if is_text(source) else os.fspath(source)


def plan_lines(plan_: PlanSource) -> tuple[list[str], str]:
    """A plan's lines and its name in messages, from any :data:`PlanSource`."""
    from csql_sim.core.files.ipc_plan import MAX_PLAN_BYTES

    if isinstance(plan_, Plan):
        return list(plan_.lines), "plan"
    if is_text(plan_):
        return str(plan_).splitlines(), "plan"
    if isinstance(plan_, (str, os.PathLike)):
        return read_text_file(plan_, MAX_PLAN_BYTES, "plan file").splitlines(), os.fspath(plan_)
    return [item if isinstance(item, str) else action_line(tuple(item)) for item in plan_], "plan"


def validate(problem: Source, plan: PlanSource, domain: Source | None = None) -> Validation:
    """Check a plan symbolically from the problem's start: every step applicable, the goal reached.

    Args:
        problem: the problem file, or its PDDL text.
        plan: a plan file, its text, a list of lines or of tuples, or a :class:`Plan`.
        domain: the domain file or text (optional); with it, actions outside it are errors.

    Returns:
        The verdict: ``valid``, and one line per error naming the step and what fails.

    Raises:
        CsqlError: one line when the problem or the plan file cannot be read.

    Example:
        >>> import csql_sim
        >>> problem = '''(define (problem two) (:domain blocks) (:objects amber pearl)
        ...   (:init (handempty) (on amber pearl) (ontable pearl) (clear amber))
        ...   (:goal (on pearl amber)))'''
        >>> csql_sim.validate(problem, [("unstack", "amber", "pearl"), ("put-down", "amber"),
        ...                             ("pick-up", "pearl"), ("stack", "pearl", "amber")]).valid
        True
        >>> verdict = csql_sim.validate(problem, ["(pick-up pearl)"])
        >>> verdict.valid, verdict.errors[0].split(": ")[-1]
        (False, 'pearl is not clear (amber is on it)')
    """
    blocks = read_blocks(problem, domain)
    lines, source = plan_lines(plan)
    count = sum(1 for line in lines if line.split(";", 1)[0].strip())
    try:
        steps = parse_plan(lines, blocks.index, blocks.n, source, blocks.actions)
        end = check_plan(blocks.start, steps, blocks.objects, source)[-1]
    except PlanError as exc:
        return Validation(False, count, (str(exc),))
    final = end.named(blocks.names).named_notation()
    missing = blocks.goal.unsatisfied(end)
    if missing:
        return Validation(False, count, (f"{source}: the plan ends in {final}, which misses {' '.join(missing)}",),
                          final)
    return Validation(True, count, (), final)


__all__ = ["BUILTIN", "PLANNERS", "builtin_policy", "plan", "plan_lines", "planner_of", "policy_maker",
           "read_blocks", "validate"]
