"""``execute`` and ``train_lifted``: a plan on the simulated arm; lifted rules learned on small worlds.

:func:`execute` is :func:`csql_sim.jobs.execute.execute_problem` (the simulator is imported
only when it runs); :func:`train_lifted` is LQ-CS (:mod:`csql_sim.learners.lifted.ql`,
a committee over generated features: :mod:`csql_sim.learners.lifted.committee`), whose rule file
:func:`csql_sim.api.plan` reads as ``rules``.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

from csql_sim.api.planning import PlanSource, Source, is_text, plan_lines, read_blocks
from csql_sim.api.planning import plan as plan_problem
from csql_sim.api.results import Execution, LiftedRules
from csql_sim.infra.errors import CsqlError

if TYPE_CHECKING:
    from csql_sim.sim.video import VideoOptions

DEFAULT_COMMITTEE = 3
"""Populations a run over generated features learns by default (``docs/features.md``: every seed's committee of
three is above GN1 at n = 20, where one population's median is below it)."""


def execute(problem: Source, plan: PlanSource | None = None, domain: Source | None = None,
            video: str | os.PathLike | None = None, rules: str | os.PathLike | None = None,
            planner: str | None = None, seed: int = 0, perception: str = "pose", perturb: bool = False,
            progress: bool = False, video_options: VideoOptions | None = None) -> Execution:
    """Run a problem's plan on the simulated Panda, closed loop; success from perception.

    Args:
        problem: the problem file, or its PDDL text (2..30 blocks: the arm's cubes).
        plan: the plan (a file, its text, lines, tuples or a :class:`~csql_sim.api.results.Plan`);
            checked symbolically before any physics runs. Default: the plan of
            :func:`csql_sim.api.plan` with the built-in rules.
        domain: its domain file or text (optional).
        video: write the episode's video here (``.mp4`` or ``.gif``, 640x480) and its
            provenance ``<video>.json``.
        rules: follow a rule file's policy on the arm instead of a plan.
        planner: ``"bfs"`` or ``"gn1"`` instead of a plan.
        seed: the episode's seed.
        perception: ``"pose"`` or ``"camera"``.
        perturb: jitter the start, nudge a cube, drop a carried cube.
        progress: progress bars on stderr.
        video_options: the video's size, frame rate, speed, renderer and workers
            (default :class:`~csql_sim.sim.video.VideoOptions`: 640x480, made for a CPU).

    Raises:
        CsqlError: one line for bad input, before any physics runs.

    Example:
        >>> import csql_sim
        >>> run = csql_sim.execute('''(define (problem two) (:domain blocks) (:objects amber pearl)
        ...   (:init (handempty) (on amber pearl) (ontable pearl) (clear amber))
        ...   (:goal (on pearl amber)))''')
        >>> run.reached, run.actions, run.final
        (True, 4, 'amber pearl')
    """
    from csql_sim.jobs.execute import execute_blocks, execute_problem
    from csql_sim.sim.world import check_arm_blocks

    blocks = read_blocks(problem, domain)
    check_arm_blocks(blocks.n)  # 2..30 cubes, before any planning
    if plan is None and rules is None and planner is None:
        plan = plan_problem(problem, domain)
        if not plan.solved:
            raise CsqlError(f"the built-in rules do not solve {blocks.name}: {plan.reason}")
    if plan is not None and (is_text(plan) or not isinstance(plan, (str, os.PathLike))):
        plan = plan_lines(plan)[0]  # a file stays a file: its hash goes in the provenance
    options = {"plan": plan, "rules": rules, "planner": planner, "seed": seed, "perception": perception,
               "perturb": perturb, "video": video, "progress": progress, "video_options": video_options}
    if is_text(problem) or is_text(domain):
        result = execute_blocks(blocks, **options)
    else:
        result = execute_problem(problem, domain, **options)
    return execution_of(result, blocks.names)


def execution_of(result, names: Sequence[str]) -> Execution:  # noqa: ANN001 - an ExecuteResult
    """The :class:`Execution` record of an executor's result, in the problem's names."""
    from csql_sim.sim.world import parse_arm_state

    final = None if result.final is None else \
        parse_arm_state(result.final, len(names)).named(tuple(names)).named_notation()
    length = getattr(result.episode, "length", len(result.steps))
    return Execution(result.reached, result.reason, length, final, result.video, tuple(names), result)


def train_lifted(out: str | os.PathLike | None = None, trials: int = 3000, sizes: Sequence[int] = (5,),
                 goals: int | None = None, features: str = "given", formulation: str | None = None,
                 domain: str | os.PathLike | None = None, complexity: int | None = None,
                 committee: int | None = None, atoms: Sequence[str] | None = None, seed: int = 0,
                 workers: int | None = 1, progress: Callable[[int, int], None] | None = None) -> LiftedRules:
    """Learn lifted Q-classifiers on small worlds (LQ-CS); they plan any number of blocks.

    Args:
        out: the rule file to write (JSON), or None to keep the text only.
        trials: training trials, >= 1 (default 3000).
        sizes: numbers of blocks trained on, among 3, 4, 5 (default 5).
        goals: training goals per size (default 40; 200 with generated features in the move domain).
        features: ``"given"`` (hand-written atoms) or ``"generated"`` (from the domain's predicates).
        formulation: with generated features: the shipped formulation, ``"4op"`` (default) or ``"move"``.
        domain: with generated features: a PDDL domain file to generate the features from, instead
            of ``formulation`` (not both).
        complexity: with generated features: the grammar's bound K, 1..10 (default 8).
        committee: with generated features: populations learned (default 3); else 1.
        atoms: with given atoms: the ones read (default: all but least-stuck).
        seed: the seed of the run's one generator.
        workers: processes that train a committee's members at once.
        progress: called with (trials done, trials in all) after every sweep.

    Example:
        >>> import csql_sim
        >>> rules = csql_sim.train_lifted(trials=300, sizes=(3,), seed=0)
        >>> p = csql_sim.plan('''(define (problem four) (:domain blocks) (:objects a b c d)
        ...   (:init (handempty) (on a b) (on b c) (on c d) (ontable d) (clear a))
        ...   (:goal (and (on d c) (on c b) (on b a))))''', rules=rules)
        >>> rules.trials, p.planner, p.solved, p.length == p.optimal_length
        (300, 'rules', True, True)
    """
    import numpy as np

    from csql_sim.learners.lifted import LiftedParams, train_committee
    from csql_sim.learners.lifted import train_lifted as learn

    if atoms is not None and features == "generated":
        raise CsqlError("atoms chooses among the given atoms; do not give it with generated features")
    size = committee if committee is not None else DEFAULT_COMMITTEE if features == "generated" else 1
    if size > 1 and features != "generated":
        raise CsqlError("a committee needs generated features")
    if formulation is not None and domain is not None:
        raise CsqlError(f"give formulation {formulation!r} or domain {os.fspath(domain)!r} (a PDDL domain), not both")
    read = {} if atoms is None else {"atoms": tuple(atoms)}
    chosen = {} if complexity is None else {"complexity": complexity}
    params = LiftedParams(trials=trials, sizes=tuple(sizes), goals=goals, features=features,
                          domain=os.fspath(domain) if domain is not None else formulation or "4op", **chosen, **read)
    rng = np.random.default_rng(seed)
    if size > 1:
        runs = train_committee(params, rng, size, progress=progress, workers=workers).members
    else:
        runs = (learn(params, rng, progress=progress),)
    return _rules(runs, params, seed, size, out)


def _training(run) -> dict:  # noqa: ANN001 - a LiftedRun
    """What one population's training did and cost, for the file's ``meta``."""
    training = {"trials": run.trials, "steps": run.steps, "seconds": round(run.seconds, 1), "reached": run.reached,
                "ground_q_classifiers": run.ground, "covered": run.covered, "specializations": run.splits,
                "generalizations": run.merges, "lifted_q_classifiers": len(run.classifiers)}
    if run.features:
        training["features"] = run.features
    return training


def _rules(runs: tuple, params, seed: int, size: int, out: str | os.PathLike | None) -> LiftedRules:  # noqa: ANN001
    """The rule file of the learned populations, written to ``out`` when given."""
    from csql_sim.core.policies.committee_policy import dumps_committee
    from csql_sim.core.policies.feature_policy import dumps_feature_policy
    from csql_sim.core.policies.lifted_policy import dumps_lifted_policy
    from csql_sim.infra.files import write_or_keep
    from csql_sim.infra.provenance import provenance

    run = runs[0]
    training = _training(run) if len(runs) == 1 else {"committee": len(runs), "members": [_training(r) for r in runs]}
    meta = {"method": "lq-cs", "seed": seed, "params": params.as_dict(), "training": training,
            "provenance": provenance(seed=seed, params=params, committee=size)}
    if len(runs) > 1:
        text = dumps_committee([(r.classifiers, r.literals) for r in runs], run.domain,
                               run.features["formulation"], meta, run.tie)
    elif run.literals:
        text = dumps_feature_policy(run.classifiers, run.literals, run.domain, run.features["formulation"], meta,
                                    run.tie)
    else:
        text = dumps_lifted_policy(run.classifiers, meta)
    path = None if out is None else write_or_keep([(out, text)])[0]
    classifiers = tuple(c.text() for r in runs for c in r.policy().classifiers)
    return LiftedRules(path, text, classifiers, sum(r.trials for r in runs), sum(r.seconds for r in runs),
                       tuple(runs), meta)


__all__ = ["DEFAULT_COMMITTEE", "execute", "execution_of", "train_lifted"]
