"""``plan`` and ``validate``: a blocks-world PDDL problem, from a path or its text, to a plan and a verdict.

A problem (and a domain) is a path or the PDDL text itself (:func:`read_blocks`). The
default planner is the shipped lifted rules (``rules="builtin"``, the file of
:func:`csql_sim.infra.assets.builtin_rules_path`, as ``--rules builtin`` on the command line),
which plan up to :data:`~csql_sim.core.files.pddl_import.MAX_PLANNED_BLOCKS` objects; a rule
file from ``csql-sim train-lifted``, ``planner="bfs"`` (up to six blocks) or a named baseline
(``"gn1"``, ``"gn2"``: :data:`csql_sim.jobs.baselines.NAMED_POLICIES`) plan instead when asked.
The work is :func:`csql_sim.jobs.plan_problems.plan_problem`; the verdict of :func:`validate`
is :func:`csql_sim.core.files.validate.validate_plan`'s, as ``csql-sim validate`` gives it.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence

from csql_sim.api.results import ActionTuple, LiftedRules, Plan, Validation, action_line, action_tuple
from csql_sim.core.files.ipc_plan import parse_plan
from csql_sim.core.files.pddl_import import (
    MAX_PDDL_BYTES,
    MAX_PLANNED_BLOCKS,
    BlocksProblem,
    parse_problem_text,
    read_problem,
)
from csql_sim.core.files.validate import validate_plan
from csql_sim.core.policies.contract import Policy
from csql_sim.infra.assets import BUILTIN_RULES, builtin_rules_path
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.files import read_text_file
from csql_sim.jobs.baselines import NAMED_POLICIES
from csql_sim.jobs.plan_problems import plan_problem

Source = str | os.PathLike
"""A path, or (a string holding a parenthesis) the text itself."""
PlanSource = Source | Sequence[str] | Sequence[ActionTuple] | Plan
"""A plan: a plan file, its text, a list of lines ``"(unstack a b)"`` or tuples ``("unstack", "a", "b")``, a Plan."""
BUILTIN = BUILTIN_RULES
"""The name of the shipped lifted rules (``rules="builtin"``, ``--rules builtin``)."""
PLANNERS = (BUILTIN, "rules", "bfs", *NAMED_POLICIES)
"""Who may plan: the shipped rules, a rule file, breadth-first search, or a named baseline (gn1, gn2)."""


def is_text(source: object) -> bool:
    """Whether ``source`` is PDDL (or plan) text rather than a path: a string with a parenthesis."""
    return isinstance(source, str) and "(" in source


def path_source(path: str | os.PathLike | None) -> Source | None:
    """A path given as a string (on a command line), as the API takes it: a Path where it would read as text."""
    from pathlib import Path

    return Path(path) if is_text(path) else path


def read_blocks(problem: Source, domain: Source | None = None, max_blocks: int = MAX_PLANNED_BLOCKS) -> BlocksProblem:
    """A blocks-world problem from a path or PDDL text (its domain likewise, optional)."""
    if not is_text(problem) and not is_text(domain):
        return read_problem(problem, domain, max_blocks=max_blocks)
    text = problem if is_text(problem) else read_text_file(problem, MAX_PDDL_BYTES, "PDDL problem")
    domain_text = None if domain is None else domain if is_text(domain) else \
        read_text_file(domain, MAX_PDDL_BYTES, "PDDL domain")
    source = "problem" if is_text(problem) else os.fspath(problem)
    return parse_problem_text(text, source, domain_text, max_blocks=max_blocks)


def planner_of(rules: Source | LiftedRules | None, planner: str | None) -> str:
    """Who plans, from ``rules`` and ``planner`` (see :func:`plan`); a CsqlError for a contradiction."""
    if planner is not None and planner not in PLANNERS:
        raise CsqlError(f"planner must be one of {', '.join(PLANNERS)}, got {planner!r}")
    if planner is None:
        return BUILTIN if rules is None or rules == BUILTIN else "rules"
    if planner == "rules" and rules is None:
        raise CsqlError("planner 'rules' needs rules (a rule file or 'builtin')")
    if (planner == "bfs" or planner in NAMED_POLICIES) and rules is not None:
        raise CsqlError(f"planner {planner!r} reads no rules; give rules or the planner, not both")
    return BUILTIN if planner == "rules" and rules == BUILTIN else planner


def policy_maker(rules: Source | LiftedRules | None, planner: str, progress: bool = False) -> Callable[[int], Policy]:
    """The planner's policy for a problem of n blocks (loaded once; CsqlError where it cannot plan n)."""
    from csql_sim.core.policies.loader import load_policy, loads_lifted_file

    cache: dict[int, Policy] = {}

    def make(n: int) -> Policy:
        if n not in cache:
            if isinstance(rules, LiftedRules):
                cache[n] = loads_lifted_file(rules.text, "the rules of train_lifted")
            elif planner in NAMED_POLICIES:
                cache[n] = NAMED_POLICIES[planner]()
            else:
                path = builtin_rules_path() if planner == BUILTIN else rules if planner == "rules" else None
                cache[n] = load_policy(path, n, progress=progress)
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
        planner: ``"builtin"``, ``"rules"`` (``rules``), ``"bfs"`` (optimal, up to six blocks),
            ``"gn1"`` or ``"gn2"`` (the named baselines); default: ``rules``, else the built-in rules.
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
    # a file is read by the job (its time counted, as the CLI reports it); a text is read here
    given = read_blocks(problem, domain) if is_text(problem) or is_text(domain) else None
    report = plan_problem(_shown(problem), None if given is not None else domain, policy_maker(rules, chosen, progress),
                          chosen, optimum_budget, blocks=given)
    blocks = report.problem_doc
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

    The verdict is :func:`csql_sim.core.files.validate.validate_plan`'s, the one ``csql-sim
    validate`` prints.

    Args:
        problem: the problem file, or its PDDL text.
        plan: a plan file, its text, a list of lines or of tuples, or a :class:`Plan`.
        domain: the domain file or text (optional); with it, actions outside it are refused.

    Returns:
        The verdict: ``valid``, and one line per error: the first step whose precondition fails
        (its number, its line and the precondition), or each goal atom that does not hold at the end.

    Raises:
        CsqlError: one line when the problem or the plan file cannot be read, or a plan line is not
            an action of the problem (an unknown action or object, a wrong number of arguments).

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
    verdict = validate_plan(blocks, parse_plan(lines, blocks.index, blocks.n, source, blocks.actions))
    return Validation(verdict.valid, verdict.steps, verdict.errors, verdict.applied, verdict.end.named_notation(),
                      verdict)


__all__ = ["BUILTIN", "PLANNERS", "path_source", "plan", "plan_lines", "planner_of", "policy_maker",
           "read_blocks", "validate"]
