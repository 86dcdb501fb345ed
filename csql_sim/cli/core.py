"""Subcommands of the symbolic core: ``states``, ``rules`` and ``plan``."""

from __future__ import annotations

import argparse
import json

from csql_sim.cli.args import blocks_arg, seed_arg
from csql_sim.errors import CsqlError
from csql_sim.message import action_code, format_action_message, format_state_message
from csql_sim.notation import parse_state_arg
from csql_sim.policy import Policy, load_policy, rollout
from csql_sim.r_classifier import r_classifiers
from csql_sim.world import BlocksWorld, State, WorldError


def read_task(start: str, goal: str, n: int | None) -> tuple[State, State]:
    """Parse a start and goal configuration (or n=3 state messages) of one world."""
    s = parse_state_arg(start, n)
    g = parse_state_arg(goal, n if n is not None else s.n)
    if s.n != g.n:
        raise WorldError(f"start {start!r} has {s.n} blocks but goal {goal!r} has {g.n}")
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
    if args.json:
        print(json.dumps({"blocks": args.blocks, "count": len(rows), "states": rows}, indent=1))
        return 0
    print(f"{len(rows)} states for {args.blocks} blocks (message goal field = the state's own code)")
    for r in rows:
        print(f"{r['index']:>5}  {r['notation']:<14} {r['message']}")
    return 0


# ------------------------------------------------------------------ rules
def cmd_rules(args: argparse.Namespace) -> int:
    rules = r_classifiers(args.blocks)
    if args.json:
        print(json.dumps([{"kind": c.kind, "condition": c.condition, "action": c.action} for c in rules], indent=1))
        return 0
    for c in rules:
        print(f"{c.kind} {c.condition} {c.action}")
    return 0


# ------------------------------------------------------------------ plan
def _plan_json(start: State, goal: State, actions) -> dict:
    n = start.n
    return {
        "start": start.notation(),
        "goal": goal.notation(),
        "plan": [
            {"code": action_code(a, n), "name": a.name(), "message": format_action_message(a, n)} for a in actions
        ],
        "length": len(actions),
    }


def _policy_for(args: argparse.Namespace) -> Policy:
    planner = args.planner or ("rules" if args.rules else "bfs")
    if planner == "rules" and not args.rules:
        raise CsqlError("--planner rules needs --rules FILE")
    return load_policy(args.rules if planner == "rules" else None, args.blocks)


def cmd_plan(args: argparse.Namespace) -> int:
    if args.all:
        if args.pairs not in (None, "all"):
            raise CsqlError("--all is --pairs all; give one of them")
        args.pairs = "all"
    policy = _policy_for(args)
    n = policy.blocks or args.blocks
    if args.pairs is not None:
        if args.start or args.goal:
            raise CsqlError("--pairs plans many pairs; do not give --start or --goal")
        return _plan_pairs(args, policy, n or 3)
    if not args.start or not args.goal:
        raise CsqlError("plan needs --start and --goal (or --pairs all|K)")
    start, goal = read_task_for_rules(args.start, args.goal, n, args.rules if args.planner != "bfs" else None)
    result = rollout(policy, start, goal)
    if not result.reached:
        raise CsqlError(f"no plan from {start.notation()} to {goal.notation()}: {result.reason}")
    if args.json:
        print(json.dumps(_plan_json(start, goal, result.actions), indent=1))
    else:
        for a in result.actions:
            print(a.name())
    return 0


def _plan_pairs(args: argparse.Namespace, policy: Policy, n: int) -> int:
    """``plan --pairs all|K``: stream each pair's plan, count the covered and optimal ones."""
    from csql_sim.pair_check import plan_pairs
    from csql_sim.rule_table import GreedyTable

    table = policy if isinstance(policy, GreedyTable) else None
    world = BlocksWorld.of(n)
    names = [a.name() for a in world.actions]
    notation = [s.notation() for s in world.states]
    total = covered = optimal = 0
    bad = []
    if args.json:
        print('{"plans": [', end="")
    for r in plan_pairs(n, table, args.pairs, args.seed):
        total += 1
        covered += r.reached
        optimal += r.optimal
        if not r.optimal and len(bad) < 5:
            bad.append(r)
        if args.json:
            entry = {"start": notation[r.start], "goal": notation[r.goal],
                     "length": len(r.actions) if r.reached else None, "optimal_length": r.optimal_length,
                     "plan": [names[a] for a in r.actions] if r.reached else None}
            print(("" if total == 1 else ",") + "\n " + json.dumps(entry), end="")
    if args.json:
        print(f'\n], "pairs": {total}, "covered": {covered}, "optimal": {optimal}}}')
    else:
        print(f"pairs: {total}  covered: {covered}  optimal: {optimal}")
        for r in bad:
            what = r.reason or f"length {len(r.actions)}, optimal {r.optimal_length}"
            print(f"  {notation[r.start]} -> {notation[r.goal]}: {what}")
    return 0 if optimal == total else 1


def _pairs_arg(text: str) -> str | int:
    from csql_sim.pairs import parse_pairs

    try:
        return parse_pairs(text)
    except CsqlError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def register(sub: argparse._SubParsersAction) -> None:
    """Add ``states``, ``rules`` and ``plan`` to the subparsers."""
    p = sub.add_parser("states", help="list every state of the n-block world")
    p.add_argument("--blocks", type=blocks_arg, default=3, help="number of blocks, 2..6 (default 3)")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_states)

    p = sub.add_parser("rules", help="print the R-classifiers (Figure 5 for n=3)")
    p.add_argument("--blocks", type=blocks_arg, default=3, help="number of blocks, 2..6 (default 3)")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_rules)

    p = sub.add_parser("plan", help="plan from a start to a goal configuration")
    p.add_argument("--start", help="start configuration, e.g. CBA (A on B on C), or an n=3 state message")
    p.add_argument("--goal", help="goal configuration, e.g. BAC")
    p.add_argument("--blocks", type=blocks_arg, help="number of blocks (default: from the configuration)")
    p.add_argument("--planner", choices=("bfs", "rules"), help="bfs (default) or rules (default with --rules)")
    p.add_argument("--rules", help="a rule base from 'csql-sim train': plan greedily from its Q-classifiers")
    p.add_argument("--pairs", type=_pairs_arg, default=None,
                   help="plan every ordered pair of distinct states (all) or a seeded sample of K, streamed; "
                        "print a summary")
    p.add_argument("--seed", type=seed_arg, default=0, help="seed of the --pairs sample (default 0)")
    p.add_argument("--all", action="store_true", help="the same as --pairs all")
    p.add_argument("--json", action="store_true", help="print JSON")
    p.set_defaults(func=cmd_plan)
