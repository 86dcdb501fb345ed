"""Subcommands of the symbolic core: ``states``, ``rules`` and ``plan``."""

from __future__ import annotations

import argparse
import json
from collections.abc import Sequence

from csql_sim.cli.args import (
    DeprecatedAlias,
    add_json,
    add_planner,
    add_quiet,
    blocks_arg,
    blocks_help,
    command_parser,
    large_blocks_arg,
    path_arg,
    say,
    seed_arg,
    show_progress,
)
from csql_sim.cli.large_plan import large_blocks, plan_large, select_policy
from csql_sim.cli.output import REPORT_VERSION, command_parameters, emit, json_stream
from csql_sim.core.classifiers.r_classifier import r_classifiers
from csql_sim.core.model.search import distance
from csql_sim.core.policies.policy import Policy
from csql_sim.core.policies.rollout import rollout
from csql_sim.core.state.message import (
    action_code,
    format_action_message,
    format_state_message,
    is_state_message,
    parse_state_message,
)
from csql_sim.core.state.notation import parse_state_arg
from csql_sim.core.state.world import Action, BlocksWorld, State, WorldError
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.outputs import Outputs
from csql_sim.infra.provenance import provenance


def read_task(start: str, goal: str | None, n: int | None) -> tuple[State, State]:
    """Parse a start and goal configuration (or n=3 state messages) of one world.

    A state message given as the start (the index form, or the goal form of
    :mod:`csql_sim.core.state.goal_message`) carries its own goal: it is used when ``goal`` is
    None, and a ``goal`` that names another state is an error.
    """
    from csql_sim.core.state.goal_message import is_goal_message, read_goal_message

    message_goal = None
    if is_goal_message(start.strip()):
        read = read_goal_message(start.strip(), n)
        s, message_goal = read.state, read.goal
    elif is_state_message(start.strip()):
        parsed = parse_state_message(start.strip(), n)
        s = parsed.state
        message_goal = BlocksWorld.of(s.n).states[parsed.goal]
    else:
        s = parse_state_arg(start, n)
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


# ------------------------------------------------------------------ states
def cmd_states(args: argparse.Namespace) -> int:
    world = BlocksWorld.of(args.blocks)
    rows = [
        {"index": i, "notation": s.notation(), "message": format_state_message(s, i)}
        for i, s in enumerate(world.states)
    ]

    def text() -> list[str]:
        head = f"{len(rows)} states for {args.blocks} blocks (message goal field = the state's own code)"
        return [head, *(f"{r['index']:>5}  {r['notation']:<14} {r['message']}" for r in rows)]

    emit(args, {"blocks": args.blocks, "count": len(rows), "states": rows}, text)
    return 0


# ------------------------------------------------------------------ rules
def cmd_rules(args: argparse.Namespace) -> int:
    rules = r_classifiers(args.blocks)
    rows = [{"kind": c.kind, "condition": c.condition, "action": c.action} for c in rules]
    emit(args, {"blocks": args.blocks, "count": len(rows), "rules": rows},
         lambda: [f"{r['kind']} {r['condition']} {r['action']}" for r in rows])
    return 0


# ------------------------------------------------------------------ plan
def plan_steps(actions: Sequence[Action], n: int) -> list[dict]:
    """The JSON of a plan: one ``{"code", "name", "message"}`` object per action."""
    return [{"code": action_code(a, n), "name": a.name(), "message": format_action_message(a, n)} for a in actions]


def declare_plan(args: argparse.Namespace, outputs: Outputs) -> None:
    """``plan`` reads ``--rules`` (no output may be that file) and may write ``--plan-out``."""
    outputs.input(args.rules, "rule file")
    if args.plan_out is not None:
        if args.pairs is not None:
            raise CsqlError("--plan-out writes the plan of one --start/--goal task; it does not go with --pairs "
                            "(use --json for the plans of many pairs)")
        outputs.file(args.plan_out, "plan file", "pddl", option="--plan-out")


def cmd_plan(args: argparse.Namespace) -> int:
    large = large_blocks(args)
    if large is not None:  # past six blocks: relational states, lifted policies (cli/large_plan.py)
        return plan_large(args, large)
    policy = select_policy(args, args.blocks)
    n = policy.blocks or args.blocks
    if args.pairs is not None:
        if args.start or args.goal:
            raise CsqlError("--pairs plans many pairs; do not give --start or --goal")
        return _plan_pairs(args, policy, n or 3)
    if not args.start:
        raise CsqlError("plan needs --start and --goal (or --pairs all|K)")
    start, goal = read_task_for_rules(args.start, args.goal, n, args.rules if args.planner != "bfs" else None)
    result = rollout(policy, start, goal)
    doc = {"start": start.notation(), "goal": goal.notation(), "blocks": start.n,
           "plan": plan_steps(result.actions, start.n) if result.reached else None,
           "length": len(result.actions) if result.reached else None,
           "optimal_length": distance(start, goal), "reason": result.reason}
    if not result.reached:
        emit(args, doc)
        say(args, "error", f"no plan from {start.notation()} to {goal.notation()}: {result.reason}")
        return 1
    if args.plan_out is not None:
        from csql_sim.core.files.ipc_plan import write_ipc_plan
        from csql_sim.infra.outputs import PDDL_HEADER

        header = f"{PDDL_HEADER} plan {start.notation()} -> {goal.notation()} (objects a, b, ... are blocks A, B, ...)"
        write_ipc_plan(result.actions, args.plan_out, header=header)
    if start == goal:
        emit(args, doc, f"the start {start.notation()} is the goal: 0 actions")
    else:
        emit(args, doc, lambda: [a.name() for a in result.actions])
    return 0


def _plan_pairs(args: argparse.Namespace, policy: Policy, n: int) -> int:
    """``plan --pairs all|K``: stream each pair's plan, count the covered and optimal ones.

    With ``--json`` the plans are streamed into one JSON object (stdout or the file):
    ``{"format": "csql-sim plan pairs report", "version": 1, "blocks", "plans": [...],
    "pairs", "covered", "optimal", "provenance"}``, one object per pair.
    """
    from tqdm import tqdm

    from csql_sim.core.model.pairs import check_sample_size, pair_count
    from csql_sim.core.policies.rollout import check_pairs

    world = BlocksWorld.of(n)
    total_pairs = pair_count(len(world.states))
    if args.pairs != "all":
        check_sample_size(args.pairs, total_pairs)
    steps = plan_steps(world.actions, n)
    notation = [s.notation() for s in world.states]
    total = covered = optimal = 0
    bad = []
    with json_stream(args) as out, tqdm(total=total_pairs if args.pairs == "all" else args.pairs, desc="pairs",
                                        unit="pair", disable=not show_progress(args), leave=False, delay=1.0,
                                        mininterval=0.5) as bar:
        if out is not None:
            head = {"format": "csql-sim plan pairs report", "version": REPORT_VERSION, "blocks": n}
            out.write(json.dumps(head)[:-1] + ', "plans": [')
        for r in check_pairs(policy, n, args.pairs, args.seed):
            total += 1
            covered += r.reached
            optimal += r.optimal
            bar.update()
            if not r.optimal and len(bad) < 5:
                bad.append(r)
            if out is not None:
                entry = {"start": notation[r.start], "goal": notation[r.goal],
                         "length": len(r.actions) if r.reached else None, "optimal_length": r.optimal_length,
                         "optimal": r.optimal, "plan": [steps[a] for a in r.actions] if r.reached else None,
                         "reason": r.reason}
                out.write(("" if total == 1 else ",") + "\n " + json.dumps(entry))
        if out is not None:
            tail = {"pairs": total, "covered": covered, "optimal": optimal,
                    "provenance": provenance(**command_parameters(args))}
            out.write("\n], " + json.dumps(tail)[1:] + "\n")
    if out is None:
        print(f"pairs: {total}  covered: {covered}  optimal: {optimal}")
        if policy.name == "bfs":
            print("  (the BFS planner checked against BFS, the yardstick itself; "
                  "give --rules FILE to check a rule base)")
        for r in bad:
            what = r.reason or f"length {len(r.actions)}, optimal {r.optimal_length}"
            print(f"  {notation[r.start]} -> {notation[r.goal]}: {what}")
    return 0 if optimal == total else 1


def _pairs_arg(text: str) -> str | int:
    from csql_sim.core.model.pairs import parse_pairs

    try:
        return parse_pairs(text)
    except CsqlError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


class _AllPairs(DeprecatedAlias):
    """``plan --all``: the old spelling of ``--pairs all``."""

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace, values: object,
                 option_string: str | None = None) -> None:  # noqa: D102
        super().__call__(parser, namespace, "all", option_string)


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``states``, ``rules`` and ``plan`` to the subparsers."""
    p = command_parser(sub, "states", "list every state of the n-block world", "csql-sim states --blocks 3")
    p.add_argument("--blocks", type=blocks_arg, default=3, help=blocks_help(2, 6, 3))
    add_json(p)
    p.set_defaults(func=cmd_states)

    p = command_parser(sub, "rules", "print the R-classifiers (Figure 5 for n=3)", "csql-sim rules --blocks 3")
    p.add_argument("--blocks", type=blocks_arg, default=3, help=blocks_help(2, 6, 3))
    add_json(p)
    p.set_defaults(func=cmd_rules)

    p = command_parser(sub, "plan", "plan from a start to a goal configuration, or over many pairs",
                       "csql-sim plan --start CBA --goal BAC")
    p.add_argument("--start", help="start configuration, e.g. CBA (A on B on C), or a state message (with its goal)")
    p.add_argument("--goal", help="goal configuration, e.g. BAC (default: the goal of a state message --start)")
    p.add_argument("--blocks", type=large_blocks_arg,
                   help=blocks_help(2, 26, "from the configuration, or 3 with --pairs",
                                    "; past 6 the states are relational and the planner lifted: gn1, or lifted "
                                    "--rules"))
    add_planner(p, "up to 6 blocks; gn1 and lifted rules: any n")
    p.add_argument("--rules", type=path_arg,
                   help="a rule base from 'csql-sim train' (plan greedily from its Q-classifiers), a sharded rule "
                        "base, or lifted rules from 'csql-sim train-lifted' (any n)")
    p.add_argument("--pairs", type=_pairs_arg, default=None,
                   help="plan every ordered pair of distinct states (all; up to 6 blocks) or a seeded sample of "
                        "K (past 6 blocks drawn uniformly by counting), streamed; print a summary")
    p.add_argument("--seed", type=seed_arg, default=0, help="seed of the --pairs sample (default 0)")
    p.add_argument("--all", dest="pairs", nargs=0, action=_AllPairs, new="--pairs all", help=argparse.SUPPRESS)
    p.add_argument("--plan-out", type=path_arg, default=None,
                   help="also write the plan as an IPC plan file (as Fast Downward writes them; "
                        "'execute --plan' reads it)")
    add_json(p)
    add_quiet(p)
    p.set_defaults(func=cmd_plan, declare=declare_plan)
