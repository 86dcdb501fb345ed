"""``plan``: one path for every number of blocks; the view of the state follows n.

The start and the goal are read by one reader (:func:`read_task`): configurations with
letters A-Z (:func:`csql_sim.core.state.notation.parse_config`), the paper's state and goal
messages (n <= 6) or relational messages (7..26,
:func:`csql_sim.core.state.relational_message.parse_large_message`); a message as ``--start``
carries its own goal. The number of blocks then picks the view:

* **n <= 6, the enumerated world**: BFS or a rule file's greedy table (lifted rules and
  ``gn1`` too), rollouts on the world model, BFS as the yardstick, the paper's messages,
  ``--pairs all|K`` over indexed pairs;
* **past six**, where nothing may be enumerated: the planner is lifted (``--planner gn1``,
  :class:`csql_sim.core.policies.gn1.Gn1Policy`, or ``--rules FILE`` for which
  :func:`csql_sim.core.policies.loader.load_policy` returns a lifted policy; BFS and
  ground rule files are refused with one line); plans run symbolically
  (:func:`csql_sim.core.policies.relational_rollout.rollout_relational`) and are measured against
  the exact optimum (:func:`csql_sim.core.measure.optimum.optimal_length`), reported, never used
  to plan; plan steps carry the relational message up to 26 blocks and ``"message": null``
  past 26; ``--pairs K`` draws K pairs uniformly by counting (:mod:`csql_sim.cli.plan_pairs`).

A single plan exits 0 when it reaches the goal, 1 when not.
"""

from __future__ import annotations

import argparse

from csql_sim.cli.args import say
from csql_sim.cli.output import emit
from csql_sim.cli.plan_pairs import plan_pairs
from csql_sim.cli.plan_problem import cmd_plan_problem, declare_problem
from csql_sim.cli.plan_view import plan_steps, select_policy
from csql_sim.core.policies.policy import Policy
from csql_sim.core.policies.relational_rollout import RelationalPolicy
from csql_sim.core.state.goal_message import is_goal_message
from csql_sim.core.state.message import is_state_message, layout
from csql_sim.core.state.notation import parse_state_arg
from csql_sim.core.state.relational_message import (
    MAX_LARGE_MESSAGE,
    infer_large_blocks,
    is_relational_message,
    message_length,
    parse_large_message,
)
from csql_sim.core.state.world import MAX_BLOCKS, MIN_BLOCKS, Action, BlocksWorld, State, WorldError
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.outputs import Outputs

# ---------------------------------------------------------------- reading the task


def _is_message(text: str) -> bool:
    """A message, not a configuration: configurations hold only letters, ``,`` and ``+``."""
    return any(ch.isdigit() or ch == "_" for ch in text)


def relational_blocks(args: argparse.Namespace) -> int | None:
    """The number of blocks of a ``plan`` job past six blocks, or None for the enumerated world.

    ``--blocks`` decides when given. Otherwise a ``--start`` that is a relational state
    message, or a configuration of more than six blocks, makes the job relational; anything
    else (including the paper's messages) stays with the enumerated world.
    """
    if args.blocks is not None:
        return args.blocks if args.blocks > MAX_BLOCKS else None
    text = (args.start or "").strip()
    if args.pairs is not None or not text:
        return None
    if _is_message(text):
        return None if is_goal_message(text) else _message_blocks(text)
    letters = sum(ch.isalpha() for ch in text)
    return letters if letters > MAX_BLOCKS else None


def _message_blocks(text: str) -> int | None:
    """The n of a relational message; None for the paper's lengths; an error naming both sets of lengths."""
    try:
        return infer_large_blocks(text)
    except CsqlError:
        paper = sorted({layout(n).length for n in range(MIN_BLOCKS, MAX_BLOCKS + 1)})
        if len(text) <= paper[-1]:
            return None  # the paper's parser names what is wrong
        raise CsqlError(f"message {text!r} has {len(text)} characters: a state message of {MIN_BLOCKS}..{MAX_BLOCKS} "
                        f"blocks has {paper[0]}..{paper[-1]}, a large one of 7..{MAX_LARGE_MESSAGE} blocks "
                        f"{message_length(MAX_BLOCKS + 1)}..{message_length(MAX_LARGE_MESSAGE)}") from None


def read_task(start: str, goal: str | None, n: int | None) -> tuple[State, State]:
    """Parse a start and a goal of one world: configurations, or state messages with their goal.

    A state message given as the start (the paper's index or goal form, or the relational
    form past six blocks) carries its own goal: it is used when ``goal`` is None, and a
    ``goal`` that names another state is an error.

    Raises:
        CsqlError: one line naming what is wrong.
    """
    from csql_sim.core.state.goal_message import read_goal_message
    from csql_sim.core.state.message import parse_state_message

    text = start.strip()
    message_goal = None
    if is_goal_message(text):
        read = read_goal_message(text, n)
        s, message_goal = read.state, read.goal
    elif is_relational_message(text):
        message = parse_large_message(text, n)
        s, message_goal = message.state, message.goal
    elif is_state_message(text):
        parsed = parse_state_message(text, n)
        s = parsed.state
        message_goal = BlocksWorld.of(s.n).states[parsed.goal]
    else:
        s = parse_state_arg(text, n)
    if goal is None:
        if message_goal is None:
            raise CsqlError("--goal is missing (only a state message as --start carries its own goal)")
        return s, message_goal
    g = parse_state_arg(goal, n if n is not None else s.n)
    if s.n != g.n:
        raise WorldError(f"start {start!r} has {s.n} blocks but goal {goal!r} has {g.n}")
    if message_goal is not None and g != message_goal:
        raise CsqlError(f"--goal {goal!r} ({g.notation()}) contradicts the goal of the start message {start!r} "
                        f"({message_goal.notation()})")
    return s, g


def read_task_for_rules(start: str, goal: str, n: int | None, rules: str | None) -> tuple[State, State]:
    """A task for a rule file of ``n`` blocks: a task of another size is an error naming the file."""
    if rules is None or n is None:
        return read_task(start, goal, n)
    s, g = read_task(start, goal, None)
    if s.n != n:
        raise CsqlError(f"rule file {rules!r} is for {n} blocks, but the task {s.notation()} -> {g.notation()} "
                        f"has {s.n}")
    return s, g


def _measured(length: int, optimum: int) -> str:
    if length == optimum:
        return f"{optimum} actions, optimal"
    return f"{length} actions, {length / optimum:.3f} x the optimum of {optimum}"


def _run(policy: Policy | RelationalPolicy, start: State, goal: State) -> tuple[tuple[Action, ...], bool, str, int]:
    """The plan's actions, whether it reached the goal, the reason when not, and the optimal length."""
    if start.n <= MAX_BLOCKS:
        from csql_sim.core.model.search import distance
        from csql_sim.core.policies.rollout import rollout

        ground = rollout(policy, start, goal)
        return tuple(ground.actions), ground.reached, ground.reason, distance(start, goal)
    from csql_sim.core.measure.optimum import optimal_length
    from csql_sim.core.policies.relational_rollout import rollout_relational

    run = rollout_relational(policy, start, goal)
    return run.actions, run.reached, run.reason, optimal_length(start, goal)  # the optimum measures only


def plan_one(args: argparse.Namespace, policy: Policy | RelationalPolicy, start: State, goal: State) -> int:
    """Plan one task and report it (text, ``--json``, ``--plan-out``); 0 when the goal is reached."""
    n, relational = start.n, start.n > MAX_BLOCKS
    actions, reached, reason, optimum = _run(policy, start, goal)
    length = len(actions) if reached else None
    doc = {"start": start.notation(), "goal": goal.notation(), "blocks": n,
           **({"planner": policy.name} if relational else {}),
           "plan": plan_steps(actions, n) if reached else None, "length": length, "optimal_length": optimum,
           **({"optimal": length == optimum} if relational else {}), "reason": reason}
    if not reached:
        emit(args, doc)
        say(args, "error", f"no plan from {start.notation()} to {goal.notation()}: {reason}")
        return 1
    if args.plan_out is not None:
        from csql_sim.core.files.ipc_plan import write_ipc_plan
        from csql_sim.infra.outputs import PDDL_HEADER

        header = f"{PDDL_HEADER} plan {start.notation()} -> {goal.notation()} (objects a, b, ... are blocks A, B, ...)"
        write_ipc_plan(actions, args.plan_out, header=header)
    if start == goal:
        emit(args, doc, f"the start {start.notation()} is the goal: 0 actions")
    elif not relational:
        emit(args, doc, lambda: [a.name() for a in actions])
    else:
        emit(args, doc, lambda: [*(f"{s['name']:<14} {s['message'] or ''}".rstrip() for s in doc["plan"]),
                                 f"{_measured(len(actions), optimum)} (exact optimum, measured after planning; "
                                 f"{policy.name} planned)"])
    return 0


def declare_plan(args: argparse.Namespace, outputs: Outputs) -> None:
    """``plan`` reads ``--rules`` (no output may be that file) and may write ``--plan-out``."""
    if args.problem is not None or args.problems is not None:
        declare_problem(args, outputs)
    outputs.input(args.rules, "rule file")
    if args.plan_out is not None and args.problems is None:  # with --problems a folder (declare_problem)
        if args.pairs is not None:
            raise CsqlError("--plan-out writes the plan of one --start/--goal task; it does not go with --pairs "
                            "(use --json for the plans of many pairs)")
        outputs.file(args.plan_out, "plan file", "pddl", option="--plan-out")


def cmd_plan(args: argparse.Namespace) -> int:
    """``plan``: one ``--start``/``--goal`` task, ``--pairs``, or PDDL ``--problem``/``--problems``."""
    if args.problem is not None or args.problems is not None or args.domain is not None:
        return cmd_plan_problem(args)
    n = relational_blocks(args)
    if args.pairs is not None and (args.start or args.goal):
        raise CsqlError("--pairs plans many pairs; do not give --start or --goal")
    if n is not None:  # past six blocks: relational states, lifted policies
        if args.pairs is not None:
            return plan_pairs(args, n)
        if not args.start:
            raise CsqlError("plan needs --start and --goal (or --pairs K)")
        start, goal = read_task(args.start, args.goal, args.blocks)
        return plan_one(args, select_policy(args, start.n), start, goal)
    policy = select_policy(args, args.blocks)
    n = policy.blocks or args.blocks
    if args.pairs is not None:
        return plan_pairs(args, n or 3, policy)
    if not args.start:
        raise CsqlError("plan needs --start and --goal (or --pairs all|K)")
    start, goal = read_task_for_rules(args.start, args.goal, n, args.rules if args.planner != "bfs" else None)
    return plan_one(args, policy, start, goal)
