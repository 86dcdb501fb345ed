"""Thirty cubes on the arm: tall-tower tasks of 12, 20 and 30 cubes, and the tallest tower; ``docs/results/arm.md``.

Regenerates docs/results/arm.md (its tables "Thirty cubes" and "The tallest tower").

Tasks are drawn as ``csql-sim problems --distribution tall-towers --max-height H --seed S``
draws them (the same generator, the same tasks), at the arm's tower limit by default,
and each runs as one closed-loop episode on the simulated Panda (scripted pick and place
by contact; success is the perceived state equal to the goal), per planner: GN1 and the
shipped lifted rules. Sizes of 10 cubes or fewer run too, as the reference of the wall
time per action (measured in the same run).

    python benchmarks/arm_thirty.py --count 20                          # 20 tasks each of 10, 12, 20, 30 cubes
    python benchmarks/arm_thirty.py --count 3 --sizes 10,30 --planners gn1 --perception camera
    python benchmarks/arm_thirty.py --towers 13,14,15,16,17             # build and take apart towers of k
    python benchmarks/arm_thirty.py --count 20 --sizes 10,30 --planners gn1 --waiting  # the ring's earlier control

Columns: reached (of the sample), mean actions (and the exact optimum's mean), sim seconds
per action (simulation steps x dt over the actions), wall seconds per action (setup, loop
and policy) and this process's CPU seconds per action (the same, less what other jobs on a
shared machine take). Bad input is one line on stderr and exit status 2.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import dataclass, replace

import numpy as np

from csql_sim.core.model.task import Task
from csql_sim.core.model.task_draws import draw_task
from csql_sim.core.policies.gn1 import Gn1Policy
from csql_sim.core.policies.loader import load_policy
from csql_sim.core.state.state import State
from csql_sim.infra.assets import builtin_rules_path
from csql_sim.infra.errors import CsqlError
from csql_sim.sim.control.executor import Episode, run_physical_episode
from csql_sim.sim.control.physical import PhysicalWorld
from csql_sim.sim.perception.rgbd import NO_NOISE, CameraNoise
from csql_sim.sim.world.arm_state import world_model_for
from csql_sim.sim.world.config import MAX_TOWER_HEIGHT, RING_CONFIG, WAITING_CONTROL, config_for

PLANNERS = ("gn1", "rules")


@dataclass
class Row:
    """The episodes of one size and planner."""

    n: int
    planner: str
    tasks: int = 0
    reached: int = 0
    actions: int = 0
    optimal: int = 0
    sim: float = 0.0
    wall: float = 0.0
    cpu: float = 0.0

    def line(self) -> str:
        k = max(1, self.tasks)
        per = max(1, self.actions)
        return (f"| {self.n} | {self.planner} | {self.reached} / {self.tasks} | {self.actions / k:.1f} "
                f"({self.optimal / k:.1f}) | {self.sim / per:.2f} | {self.wall / per:.2f} | {self.cpu / per:.2f} |")


def policy_of(name: str, n: int) -> object:
    """GN1, or the shipped lifted rules."""
    return Gn1Policy() if name == "gn1" else load_policy(str(builtin_rules_path()), n)


def run_sizes(args: argparse.Namespace) -> list[Row]:
    """Every task of every size for every planner; a progress line per episode on stderr."""
    rows = []
    for n in args.sizes:
        rng = np.random.default_rng(args.seed)
        tasks = [draw_task("tall-towers", n, rng, max_height=args.max_height) for _ in range(args.count)]
        for planner in args.planners:
            row = Row(n, planner)
            for k, (start, goal) in enumerate(tasks):
                t, c = time.perf_counter(), time.process_time()
                config = replace(RING_CONFIG, control=WAITING_CONTROL) if args.waiting and n > 10 else config_for(n)
                result = run_physical_episode(start, goal, policy_of(planner, n), seed=args.seed + k, config=config,
                                              perception=args.perception, camera_noise=args.noise)
                row.tasks += 1
                row.reached += result.success
                row.actions += result.length
                row.optimal += result.optimal_length
                row.sim += sum(s.sim_seconds for s in result.steps)
                row.wall += time.perf_counter() - t
                row.cpu += time.process_time() - c
                print(f"n={n} {planner} task {k + 1}: {'reached' if result.success else result.reason} in "
                      f"{result.length} actions (optimal {result.optimal_length}), sim "
                      f"{sum(s.sim_seconds for s in result.steps):.1f} s, wall {time.perf_counter() - t:.1f} s, "
                      f"CPU {time.process_time() - c:.1f} s", file=sys.stderr, flush=True)
            rows.append(row)
    return rows


def ratio_lines(rows: list[Row]) -> list[str]:
    """Wall and CPU seconds per action at 30 cubes over those at 10, per planner (the target: 2x)."""
    out = []
    for row in rows:
        ref = next((r for r in rows if r.n == 10 and r.planner == row.planner), None)
        if ref is None or row.n != 30 or not (ref.actions and row.actions):
            continue
        for what in ("wall", "cpu"):
            ratio = (getattr(row, what) / row.actions) / (getattr(ref, what) / ref.actions)
            out.append(f"{what} per action, 30 cubes / 10 cubes ({row.planner}): {ratio:.2f}x "
                       f"({'met' if ratio <= 2 else 'NOT met'}: target 2x)")
    return out


def tower_trial(k: int, seed: int) -> dict:
    """Build a tower of k cubes from k table spots with GN1, then take it apart, in one scene."""
    flat = State((-1,) * k)
    tower = State((-1, *range(k - 1)))
    out = {"k": k}
    with PhysicalWorld(k, seed, "pose", RING_CONFIG) as world:
        world.build(flat)
        for name, (a, b) in (("built", (flat, tower)), ("taken_apart", (tower, flat))):
            episode = Episode(Task(a, b), world, Gn1Policy(), world_model_for(k), cap=3 * k + 12, seed=seed,
                              perturbation=None, fps=None)
            result = episode.run()
            out[name] = result.success
            out[f"{name}_actions"] = result.length
            if not result.success:
                out["reason"] = result.reason
                break
    return out


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--sizes", default="10,12,20,30", help="cube counts, 2..30 (default 10,12,20,30)")
    p.add_argument("--count", type=int, default=20, help="tasks per size (default 20)")
    p.add_argument("--max-height", type=int, default=MAX_TOWER_HEIGHT, help="towers at most this high")
    p.add_argument("--planners", default="gn1,rules", help="gn1 and/or rules (the shipped lifted rules)")
    p.add_argument("--perception", choices=("pose", "camera"), default="pose", help="default pose")
    p.add_argument("--camera-noise", default="0,0", metavar="MM,LEVELS",
                   help="camera sensor noise: depth mm, colour levels (default 0,0: none, the tool's default)")
    p.add_argument("--waiting", action="store_true",
                   help="past ten cubes, the ring's earlier control (WAITING_CONTROL: every motion comes to rest)")
    p.add_argument("--seed", type=int, default=0, help="the tasks' generator and the episodes' seeds (default 0)")
    p.add_argument("--towers", help="instead: build and take apart towers of these heights (e.g. 13,14,15)")
    p.add_argument("--json", help="also write the figures here")
    args = p.parse_args(argv)
    try:
        args.sizes = [int(x) for x in args.sizes.split(",")]
        args.planners = [x.strip() for x in args.planners.split(",")]
        args.towers = [int(x) for x in args.towers.split(",")] if args.towers else None
        depth, colour = (float(x) for x in args.camera_noise.split(","))
        args.noise = CameraNoise(depth / 1000.0, colour)
    except ValueError as exc:
        p.error(str(exc))
    if args.noise != NO_NOISE and args.perception != "camera":
        p.error("--camera-noise needs --perception camera")
    if any(x not in PLANNERS for x in args.planners) or args.count < 1 or any(not 2 <= n <= 30 for n in args.sizes):
        p.error(f"planners among {', '.join(PLANNERS)}, count >= 1, sizes 2..30")
    return args


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    t0 = time.strftime("%Y-%m-%d")
    try:
        if args.towers:
            trials = [tower_trial(k, args.seed) for k in args.towers]
            for t in trials:
                print(json.dumps(t))
            doc: dict = {"date": t0, "towers": trials}
        else:
            rows = run_sizes(args)
            print(f"{t0}: tall-towers tasks, towers at most {args.max_height} high, seed {args.seed}, "
                  f"{args.count} per size, {args.perception} perception, camera noise {args.camera_noise} "
                  f"(mm, levels), ring control {'WAITING_CONTROL' if args.waiting else 'RING_CONFIG'}")
            print("| n | planner | reached | actions (optimal) | sim s / action | wall s / action | CPU s / action |")
            print("|---|---|---|---|---|---|---|")
            for row in rows:
                print(row.line())
            for line in ratio_lines(rows):
                print(line)
            doc = {"date": t0, "args": {k: v for k, v in vars(args).items() if k not in ("json", "noise")},
                   "rows": [vars(r) for r in rows]}
    except CsqlError as exc:
        print(f"arm_thirty: {exc}", file=sys.stderr)
        return 2
    if args.json:
        with open(args.json, "w") as f:
            json.dump(doc, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
