"""``plan --pairs``: many pairs, streamed, with a summary; the view follows n as for one task.

Up to six blocks ``--pairs all|K`` plans indexed pairs of the enumerated world, checked
against BFS. Past six ``--pairs K`` draws K pairs uniformly by counting
(:func:`csql_sim.core.model.pairs.stream_large_pairs`, exact integers; ``all`` and a K beyond
the number of pairs are refused up front, :func:`csql_sim.core.model.pairs.check_large_pairs`)
and measures each plan against the exact optimum. A sample exits 0 when every pair is
solved (optimally, up to six blocks), 1 otherwise.
"""

from __future__ import annotations

import argparse
import json
import math

from csql_sim.cli.args import show_progress
from csql_sim.cli.output import REPORT_VERSION, command_parameters, json_stream
from csql_sim.cli.plan_view import plan_steps, select_policy
from csql_sim.core.measure.optimum import optimal_length
from csql_sim.core.model.pairs import stream_large_pairs
from csql_sim.core.policies.policy import Policy
from csql_sim.core.policies.relational_rollout import RelationalPolicy, RelationalRollout, rollout_relational
from csql_sim.core.state.world import MAX_BLOCKS, BlocksWorld, State
from csql_sim.infra.provenance import provenance


def plan_pairs(args: argparse.Namespace, n: int, policy: Policy | None = None) -> int:
    """``plan --pairs`` of n blocks (``policy``: the one already chosen up to six blocks)."""
    if n <= MAX_BLOCKS:
        return _ground_pairs(args, policy, n)
    from csql_sim.core.model.pairs import check_large_pairs

    k = check_large_pairs(args.pairs, n)  # refused before any rule file is read
    return _relational_pairs(args, select_policy(args, n), n, k)


def _ground_pairs(args: argparse.Namespace, policy: Policy, n: int) -> int:
    """``plan --pairs all|K`` up to six blocks: stream each pair's plan, count the covered and optimal ones.

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



class _Tally:
    """Counts of a sample: solved, optimal, the sum of length / optimum over solved pairs, examples."""

    def __init__(self) -> None:
        self.total = self.solved = self.optimal = 0
        self.ratios: list[float] = []
        self.unsolved: list[str] = []
        self.longer: list[str] = []

    def add(self, start: State, goal: State, result: RelationalRollout, optimum: int) -> None:
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


def _relational_pairs(args: argparse.Namespace, policy: RelationalPolicy, n: int, k: int) -> int:
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
                         "plan": plan_steps(result.actions, n) if result.reached else None,
                         "reason": result.reason}
                out.write(("" if tally.total == 1 else ",") + "\n " + json.dumps(entry))
        if out is not None:
            tail = {**tally.summary(), "provenance": provenance(**command_parameters(args))}
            out.write("\n], " + json.dumps(tail)[1:] + "\n")
    if out is None:
        print("\n".join(tally.lines(n, args.seed, policy.name)))
    return 0 if tally.solved == tally.total else 1
