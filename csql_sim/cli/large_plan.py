"""``plan`` past six blocks (7..26): relational states, lifted policies, the exact optimum as a yardstick.

Up to six blocks ``plan`` works on the enumerated world (:mod:`csql_sim.cli.core`), exactly
as before. Past six, where nothing may be enumerated:

* the start and the goal are configurations with letters A-Z
  (:func:`csql_sim.core.state.large_state.parse_large`) or large state messages
  (:func:`csql_sim.core.state.large_message.parse_large_message`; one as ``--start`` carries its
  own goal);
* the planner is lifted: ``--planner gn1`` (the named baseline,
  :class:`csql_sim.learners.gn1.Gn1Policy`) or ``--rules FILE`` for which
  :func:`csql_sim.core.policies.loader.load_policy` returns a lifted policy (``blocks`` None);
  BFS and ground rule files are refused with one line;
* plans run symbolically (:func:`csql_sim.core.policies.relational_rollout.rollout_relational`) and
  are measured against the exact optimum (:func:`csql_sim.core.measure.optimum.optimal_length`),
  which is reported, never used to plan;
* ``--pairs K`` draws K pairs uniformly by counting (:func:`csql_sim.core.model.pairs.stream_large_pairs`,
  exact integers); ``--pairs all`` and a K beyond the number of pairs are refused up
  front (:func:`csql_sim.core.model.pairs.check_large_pairs`).

A single plan exits 0 when it reaches the goal, 1 when not. A sample exits 0 when every
pair is solved (optimality is measured, not required: optimal blocks-world planning is
NP-hard, and the lifted policies are not optimal everywhere), 1 otherwise.
"""

from __future__ import annotations

import argparse
import json
import math
from collections.abc import Sequence

from csql_sim.cli.args import say, show_progress
from csql_sim.cli.output import REPORT_VERSION, command_parameters, emit, json_stream
from csql_sim.core.measure.optimum import optimal_length
from csql_sim.core.model.pairs import check_large_pairs, stream_large_pairs
from csql_sim.core.policies.loader import load_policy
from csql_sim.core.policies.policy import Policy
from csql_sim.core.policies.relational_rollout import RelationalPolicy, RelationalRollout, rollout_relational
from csql_sim.core.state.goal_message import is_goal_message
from csql_sim.core.state.large_message import (
    format_large_action,
    infer_large_blocks,
    message_length,
    parse_large_message,
)
from csql_sim.core.state.large_state import LETTERS, LargeState, action_index, action_name, parse_large
from csql_sim.core.state.message import layout
from csql_sim.core.state.world import MAX_BLOCKS, MIN_BLOCKS, Action
from csql_sim.infra.errors import CsqlError
from csql_sim.infra.provenance import provenance
from csql_sim.learners.gn1 import Gn1Policy

# ---------------------------------------------------------------- reading the task


def _is_message(text: str) -> bool:
    """A message, not a configuration: configurations hold only letters, ``,`` and ``+``."""
    return any(ch.isdigit() or ch == "_" for ch in text)


def large_blocks(args: argparse.Namespace) -> int | None:
    """The number of blocks of a ``plan`` job past six blocks, or None for the enumerated world.

    ``--blocks`` decides when given. Otherwise a ``--start`` that is a large state message,
    or a configuration of more than six blocks, makes the job large; anything else
    (including the paper's messages) stays with the enumerated world and its parser.
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
    """The n of a large state message; None for the paper's lengths; an error naming both sets of lengths."""
    try:
        return infer_large_blocks(text)
    except CsqlError:
        paper = sorted({layout(n).length for n in range(MIN_BLOCKS, MAX_BLOCKS + 1)})
        if len(text) <= paper[-1]:
            return None  # the paper's parser names what is wrong
        raise CsqlError(f"message {text!r} has {len(text)} characters: a state message of {MIN_BLOCKS}..{MAX_BLOCKS} "
                        f"blocks has {paper[0]}..{paper[-1]}, a large one of 7..{len(LETTERS)} blocks "
                        f"{message_length(MAX_BLOCKS + 1)}..{message_length(len(LETTERS))}") from None


def _read_state(text: str, n: int | None) -> LargeState:
    text = text.strip()
    return parse_large_message(text, n).state if _is_message(text) else parse_large(text, n)


def read_large_task(start: str, goal: str | None, n: int | None) -> tuple[LargeState, LargeState]:
    """A start and goal of 7..26 blocks: configurations (A-Z) or large state messages.

    A large state message as the start carries its own goal: it is used when ``goal`` is
    None, and a ``goal`` naming another state is an error. A message as ``goal`` stands
    for its state.

    Raises:
        CsqlError: one line naming what is wrong.
    """
    text = start.strip()
    message_goal = None
    if _is_message(text):
        message = parse_large_message(text, n)
        s, message_goal = message.state, message.goal
    else:
        s = parse_large(text, n)
    if goal is None:
        if message_goal is None:
            raise CsqlError("--goal is missing (only a state message as --start carries its own goal)")
        return s, message_goal
    g = _read_state(goal, s.n)
    if message_goal is not None and g != message_goal:
        raise CsqlError(f"--goal {goal!r} ({g.notation()}) contradicts the goal of the start message {start!r} "
                        f"({message_goal.notation()})")
    return s, g


# ---------------------------------------------------------------- the planner


def select_policy(args: argparse.Namespace, n: int | None) -> Policy | RelationalPolicy:
    """The policy of ``--planner`` and ``--rules`` for a job of ``n`` blocks.

    Past six blocks only lifted rules and ``gn1`` plan: :func:`load_policy` refuses BFS and
    ground rule files there.
    """
    planner = args.planner or ("rules" if args.rules else "bfs")
    if planner == "rules" and not args.rules:
        raise CsqlError("--planner rules needs --rules FILE")
    if planner != "rules" and args.rules:
        raise CsqlError(f"--planner {planner} does not read --rules {args.rules!r}; give one of them")
    if planner == "gn1":
        return Gn1Policy()
    return load_policy(args.rules if planner == "rules" else None, n, progress=show_progress(args))


# ---------------------------------------------------------------- plans


def large_steps(actions: Sequence[Action], n: int) -> list[dict]:
    """The JSON of a plan past six blocks: ``{"code", "name", "message"}`` per action (large messages)."""
    return [{"code": action_index(a, n) + 1, "name": action_name(a), "message": format_large_action(a, n)}
            for a in actions]


def _measured(result: RelationalRollout, optimum: int) -> str:
    if result.length == optimum:
        return f"{optimum} actions, optimal"
    return f"{result.length} actions, {result.length / optimum:.3f} x the optimum of {optimum}"


def plan_large(args: argparse.Namespace, n: int) -> int:
    """``plan`` past six blocks: ``--pairs K`` or one ``--start``/``--goal`` task (see the module docstring)."""
    if args.pairs is not None:
        if args.start or args.goal:
            raise CsqlError("--pairs plans many pairs; do not give --start or --goal")
        k = check_large_pairs(args.pairs, n)  # refused before any rule file is read
        return _plan_pairs(args, select_policy(args, n), n, k)
    if not args.start:
        raise CsqlError("plan needs --start and --goal (or --pairs K)")
    start, goal = read_large_task(args.start, args.goal, args.blocks)
    policy = select_policy(args, start.n)
    return _plan_one(args, policy, start, goal)


def _plan_one(args: argparse.Namespace, policy: RelationalPolicy, start: LargeState, goal: LargeState) -> int:
    n = start.n
    result = rollout_relational(policy, start, goal)
    optimum = optimal_length(start, goal)  # measured only: the plan is already made
    doc = {"start": start.notation(), "goal": goal.notation(), "blocks": n, "planner": policy.name,
           "plan": large_steps(result.actions, n) if result.reached else None, "length": result.length,
           "optimal_length": optimum, "optimal": result.length == optimum, "reason": result.reason}
    if not result.reached:
        emit(args, doc)
        say(args, "error", f"no plan from {start.notation()} to {goal.notation()}: {result.reason}")
        return 1
    if args.plan_out is not None:
        from csql_sim.core.files.ipc_plan import write_ipc_plan
        from csql_sim.infra.outputs import PDDL_HEADER

        header = (f"{PDDL_HEADER} plan {start.notation()} -> {goal.notation()} "
                  f"(objects a, b, ... are blocks A, B, ...)")
        write_ipc_plan(result.actions, args.plan_out, names=[c.lower() for c in LETTERS[:n]], header=header)
    if start == goal:
        emit(args, doc, f"the start {start.notation()} is the goal: 0 actions")
        return 0
    emit(args, doc, lambda: [*(f"{action_name(a):<14} {format_large_action(a, n)}" for a in result.actions),
                             f"{_measured(result, optimum)} (exact optimum, measured after planning; "
                             f"{policy.name} planned)"])
    return 0


class _Tally:
    """Counts of a sample: solved, optimal, the sum of length / optimum over solved pairs, examples."""

    def __init__(self) -> None:
        self.total = self.solved = self.optimal = 0
        self.ratios: list[float] = []
        self.unsolved: list[str] = []
        self.longer: list[str] = []

    def add(self, start: LargeState, goal: LargeState, result: RelationalRollout, optimum: int) -> None:
        self.total += 1
        pair = f"{start.notation()} -> {goal.notation()}"
        if not result.reached:
            self.unsolved.append(f"{pair}: {result.reason}")
            return
        self.solved += 1
        self.optimal += result.length == optimum
        self.ratios.append(result.length / optimum)
        if result.length != optimum:
            self.longer.append(f"{pair}: length {result.length}, optimal {optimum}")

    @property
    def mean_ratio(self) -> float | None:
        return math.fsum(self.ratios) / len(self.ratios) if self.ratios else None

    def summary(self) -> dict:
        """The report's totals (percentages of all pairs; the ratio over solved pairs)."""
        ratio = self.mean_ratio
        return {"pairs": self.total, "covered": self.solved, "optimal": self.optimal,
                "solved_percent": round(100 * self.solved / self.total, 2),
                "optimal_percent": round(100 * self.optimal / self.total, 2),
                "mean_length_over_optimum": None if ratio is None else round(ratio, 6)}

    def lines(self, n: int, seed: int, planner: str) -> list[str]:
        ratio = "n/a" if self.mean_ratio is None else f"{self.mean_ratio:.4f}"
        head = (f"pairs: {self.total}  solved: {self.solved} ({100 * self.solved / self.total:.1f}%)  "
                f"optimal: {self.optimal} ({100 * self.optimal / self.total:.1f}%)  mean length / optimum: {ratio}")
        about = (f"  {n} blocks, pairs drawn uniformly by counting (seed {seed}); {planner} planned; the exact "
                 f"optimum measures, it does not plan")
        examples = self.unsolved[:5] or self.longer[:3]
        return [head, about, *(f"  {e}" for e in examples)]


def _plan_pairs(args: argparse.Namespace, policy: RelationalPolicy, n: int, k: int) -> int:
    """``plan --pairs K`` past six blocks: stream each pair's plan and its optimum; print a summary.

    With ``--json`` one object is streamed (stdout or the file): ``{"format": "csql-sim plan
    pairs report", "version": 1, "blocks", "sampling", "seed", "planner", "plans": [...],
    "pairs", "covered", "optimal", "solved_percent", "optimal_percent",
    "mean_length_over_optimum", "provenance"}``.
    """
    from tqdm import tqdm

    tally = _Tally()
    with json_stream(args) as out, tqdm(total=k, desc=f"pairs of {n} blocks", unit="pair", leave=False,
                                        disable=not show_progress(args), delay=1.0, mininterval=0.5) as bar:
        if out is not None:
            head = {"format": "csql-sim plan pairs report", "version": REPORT_VERSION, "blocks": n,
                    "sampling": "uniform by counting", "seed": args.seed, "planner": policy.name}
            out.write(json.dumps(head)[:-1] + ', "plans": [')
        for start, goal in stream_large_pairs(n, k, args.seed):
            result = rollout_relational(policy, start, goal)
            optimum = optimal_length(start, goal)
            tally.add(start, goal, result, optimum)
            bar.update()
            if out is not None:
                entry = {"start": start.notation(), "goal": goal.notation(), "length": result.length,
                         "optimal_length": optimum, "optimal": result.length == optimum,
                         "plan": large_steps(result.actions, n) if result.reached else None,
                         "reason": result.reason}
                out.write(("" if tally.total == 1 else ",") + "\n " + json.dumps(entry))
        if out is not None:
            tail = {**tally.summary(), "provenance": provenance(**command_parameters(args))}
            out.write("\n], " + json.dumps(tail)[1:] + "\n")
    if out is None:
        print("\n".join(tally.lines(n, args.seed, policy.name)))
    return 0 if tally.solved == tally.total else 1
