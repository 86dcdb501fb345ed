"""XCS-QL (this project) and xcsf side by side: trials to all pairs optimal, population size, wall time.

Regenerates docs/results/learners.md, XCS-QL beside xcsf.

Both learners see the same tasks (random ordered (start, goal) pairs of distinct states
from one seeded generator) and the same encoding: the goal form of the state message with
the detectors home, placed and ready (csql_sim.core.state.goal_message), which xcsf reads as
one binary input per (position, character) that occurs (ternary conditions, one bit per
input). Every --every trials each learner's greedy policy is checked on every pair
(csql_sim.core.model.search.count_optimal_greedy: a pair is optimal iff each greedy step lowers
the BFS distance by one); a learner is done at the first check where all pairs are.

* XCS-QL: csql_sim.learners.generalize.xcs_ql.XCSQL with the cs-ql defaults for n and no planning
  sweep (learning from trials alone, as the scaling study does); its policy is its
  condensed population; population = actors before condensation (and condensed).
* xcsf 1.5 multi-step reinforcement learning (Preen), ternary conditions, constant
  predictions, integer actions, XCS's classic settings (below); every one of the n-block
  world's actions is an action, an illegal one leaves the state as it is (as LT-QL's
  table); reward 1 at the goal; its policy is the argmax of its prediction array;
  population = macro-classifiers.

Wall time is process CPU time of learning and checks (the machine is shared).

    .venv/bin/pip install xcsf==1.5.0      # development only, never a runtime dependency
    .venv/bin/python benchmarks/learners_xcsf.py --blocks 3,4 --max-trials 3:10000,4:40000 \
        --xcsf-max-trials 3:10000,4:2000 --checks 20 --out docs/xcsf_comparison.png --json docs/xcsf_comparison.json
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np

from csql_sim.core.model.search import count_optimal_greedy
from csql_sim.core.model.transition_table import true_table
from csql_sim.core.state.goal_message import GoalForm
from csql_sim.core.state.goal_message_index import pair_messages
from csql_sim.core.state.world import BlocksWorld
from csql_sim.learners.generalize.xcs_ql import XCSQL
from csql_sim.learners.paper.params import defaults_for_blocks, with_overrides

XCSF_SETTINGS = {"pop_size": 4000, "e0": 0.01, "alpha": 0.1, "nu": 5, "beta": 0.2, "theta_sub": 20,
                 "set_subsumption": True, "gamma": 0.95, "p_explore": 0.9, "pop_init": False}


class Stop(Exception):
    """All pairs optimal."""


def encoding(n: int) -> np.ndarray:
    """One float 0/1 input per (position, character) that varies over the pairs' goal-form messages."""
    rows = pair_messages(GoalForm(n))
    columns = [rows[:, p] == v for p in range(rows.shape[1]) for v in np.unique(rows[:, p]) if
               len(np.unique(rows[:, p])) > 1]
    return np.stack(columns, axis=1).astype(np.float64)


def tasks(n: int, seed: int):
    rng = np.random.default_rng(seed)
    count = len(BlocksWorld.of(n).states)
    while True:
        s, g = rng.choice(count, 2, replace=False)
        yield int(s), int(g)


def run_xcs_ql(n: int, seed: int, max_trials: int, every: int, sweep: bool = False) -> dict:
    params = with_overrides(defaults_for_blocks("cs-ql", n), {"sweep": sweep})
    learner = XCSQL(n, params, np.random.default_rng(seed))
    pairs = len(learner.world.states) * (len(learner.world.states) - 1)
    found = {"trials": None, "optimal": 0}
    began = time.process_time()
    if sweep:  # all trials, then CS-QL's planning sweep over every pair; one check at the end
        learner.train(max_trials, test_every=0)
        learner.sweep()
        found["optimal"] = count_optimal_greedy(learner.greedy_table().best, n)
        found["trials"] = max_trials if found["optimal"] == pairs else None
        return {"learner": "xcs-ql", "blocks": n, "trials_to_all_optimal": found["trials"], "sweep": True,
                "steps": learner.t, "max_trials": max_trials, "optimal_pairs": found["optimal"],
                "pairs": pairs, "population": len(learner.population), "condensed": len(learner.condensed()),
                "cpu_seconds": round(time.process_time() - began, 2)}

    def check(k: int) -> None:
        if (k + 1) % every:
            return
        learner.revise()
        found["optimal"] = count_optimal_greedy(learner.greedy_table().best, n)
        if found["optimal"] == pairs:
            found["trials"] = k + 1
            raise Stop

    try:
        learner.train(max_trials, on_trial=check, test_every=0)
    except Stop:
        pass
    return {"learner": "xcs-ql", "blocks": n, "trials_to_all_optimal": found["trials"], "max_trials": max_trials,
            "optimal_pairs": found["optimal"], "pairs": pairs, "population": len(learner.population),
            "condensed": len(learner.condensed()), "cpu_seconds": round(time.process_time() - began, 2)}


def run_xcsf(n: int, seed: int, max_trials: int, every: int) -> dict:
    import xcsf

    world, table = BlocksWorld.of(n), true_table(n)
    count, actions = len(world.states), len(world.actions)
    x = encoding(n)
    cap = 10 * n * n
    agent = xcsf.XCS(x_dim=x.shape[1], y_dim=1, n_actions=actions, omp_num_threads=1, random_state=seed,
                     teletransportation=cap, condition={"type": "ternary", "args": {"bits": 1, "p_dontcare": 0.5}},
                     prediction={"type": "constant"}, action={"type": "integer"},
                     ea={"select_type": "roulette", "theta_ea": 25, "lambda": 2, "p_crossover": 0.8,
                         "err_reduc": 1, "fit_reduc": 0.1, "subsumption": True, "pred_reset": False},
                     **XCSF_SETTINGS)
    pairs = count * (count - 1)
    optimal, reached = 0, None
    began = time.process_time()
    source = tasks(n, seed)
    for k in range(max_trials):
        s, g = next(source)
        agent.init_trial()
        for _ in range(cap):
            agent.init_step()
            a = agent.decision(x[s * count + g], True)
            nxt = table.next_state[s, a]
            s = s if nxt < 0 else int(nxt)
            done = s == g
            agent.update(1.0 if done else 0.0, done)
            agent.end_step()
            if done:
                break
        agent.end_trial()
        if (k + 1) % every == 0:
            best = np.argmax(agent.predict(x), axis=1).astype(np.int8)
            optimal = count_optimal_greedy(best, n)
            if optimal == pairs:
                reached = k + 1
                break
    return {"learner": "xcsf", "blocks": n, "trials_to_all_optimal": reached, "max_trials": max_trials,
            "optimal_pairs": optimal, "pairs": pairs, "population": agent.pset_size(),
            "cpu_seconds": round(time.process_time() - began, 2)}


def draw(rows: list[dict], path: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    blocks = sorted({r["blocks"] for r in rows})
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.8))
    panels = (("trials_to_all_optimal", "trials to all pairs optimal\n(label: pairs optimal at the end)"),
              ("population", "final population (classifiers)\nhatched: cap reached, not all optimal"),
              ("cpu_seconds", "CPU seconds"))
    for ax, (key, title) in zip(axes, panels, strict=True):
        for j, name in enumerate(("xcs-ql", "xcsf")):
            for i, n in enumerate(blocks):
                r = next((r for r in rows if r["learner"] == name and r["blocks"] == n), None)
                if r is None:
                    continue
                value = r[key] if r[key] is not None else r["max_trials"]
                ax.bar(i + 0.38 * j, value, 0.36, color=("tab:blue", "tab:orange")[j],
                       hatch="//" if r["trials_to_all_optimal"] is None else None,
                       label=name if i == 0 else None)
                note = f"{r['optimal_pairs']}/{r['pairs']}" if key == "trials_to_all_optimal" else f"{value:g}"
                if key == "trials_to_all_optimal" and r.get("sweep"):
                    note += "\n+ sweep"
                if key == "population" and "condensed" in r:
                    note += f"\n({r['condensed']} condensed)"
                ax.annotate(note, (i + 0.38 * j, value), ha="center", va="bottom", fontsize=7)
        ax.set_xticks([i + 0.19 for i in range(len(blocks))], [f"n = {n}" for n in blocks])
        ax.set_yscale("log")
        low, high = ax.get_ylim()
        ax.set_ylim(low, high * 4)  # room for the labels
        ax.set_title(title, fontsize=9)
    axes[0].legend(fontsize=8, loc="upper left")
    fig.suptitle("XCS-QL (condensed, this project) and xcsf 1.5 on the same tasks and encoding", fontsize=10)
    fig.tight_layout(rect=(0, 0, 1, 0.95))
    fig.savefig(path, dpi=110, metadata={"Software": "csql-sim benchmarks/learners_xcsf.py"})


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--blocks", default="3", help="comma list of n (default 3)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--max-trials", default="3:50000,4:100000", help="cap per n, e.g. 3:50000,4:100000")
    parser.add_argument("--xcsf-max-trials", default=None, help="xcsf's cap per n (default: --max-trials)")
    parser.add_argument("--checks", type=int, default=100, help="checks per cap (default 100)")
    parser.add_argument("--out", help="PNG to draw")
    parser.add_argument("--json", help="JSON file for the rows")
    parser.add_argument("--sweep", action="store_true",
                        help="XCS-QL trains all --max-trials and then plans (CS-QL's sweep); checked once at the end")
    parser.add_argument("--draw", nargs="+", metavar="JSON", help="only draw --out from the rows of these JSON files")
    args = parser.parse_args()
    if args.draw:
        docs = [json.load(open(path)) for path in args.draw]
        rows = [row for doc in docs for row in doc["rows"]]
        if args.json:
            with open(args.json, "w") as fh:
                json.dump({**docs[0], "rows": rows}, fh, indent=1)
        draw(rows, args.out)
        return
    def parse(text: str) -> dict[int, int]:
        return {int(k): int(v) for k, v in (item.split(":") for item in text.split(","))}

    caps = parse(args.max_trials)
    xcsf_caps = parse(args.xcsf_max_trials) if args.xcsf_max_trials else caps
    rows = []
    for n in (int(b) for b in args.blocks.split(",")):
        for run, cap in ((run_xcs_ql, caps.get(n, 50_000)), (run_xcsf, xcsf_caps.get(n, 50_000))):
            extra = {"sweep": True} if args.sweep and run is run_xcs_ql else {}
            row = run(n, args.seed, cap, max(1, cap // args.checks), **extra)
            print(json.dumps(row), flush=True)
            rows.append(row)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump({"format": "csql-sim xcsf comparison", "version": 1, "seed": args.seed,
                       "xcsf_settings": XCSF_SETTINGS, "rows": rows}, fh, indent=1)
    if args.out:
        draw(rows, args.out)


if __name__ == "__main__":
    main()
