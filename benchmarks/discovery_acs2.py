"""Rule induction (csql_sim.discovery.induction) and ACS2 (pyalcs) side by side on one transition stream.

Regenerates docs/results/discovery.md, rule induction beside ACS2 (the figure and its JSON).

Both learners get the same stream of (state message, action, next state message) records,
symbolic and recorded from the arm, in order. Every --every transitions the script counts,
for each learner, how many of the 42 legal (state, action) transitions of the 3-block world
its reliable rules predict correctly (learning and scoring time is CPU time, the machine is shared):

* induction: the action's precondition rule matches the state and its add-delete rule
  rewrites the posted message into the successor's message (only rules that passed the
  reliability threshold exist at all);
* ACS2: among the reliable classifiers (q > theta_r) that match the state and advocate the
  action, the one with the highest q anticipates the successor (does_anticipate_correctly).

ACS2 is driven through its anticipatory learning process (ClassifiersList.apply_alp) with
the stream's actions, not its own choices; no GA, default parameters otherwise.

    pip install -e ".[dev]"   # pyalcs is a development dependency only
    python benchmarks/discovery_acs2.py --arm-log arm.jsonl --out docs/discovery_acs2.png
        --json docs/discovery_acs2.json
"""

from __future__ import annotations

import argparse
import json
import random
import time

from csql_sim.core.classifiers.r_classifier import matches
from csql_sim.core.state.message import format_action_message, format_state_message
from csql_sim.core.state.world import all_actions, all_states, is_legal, successor
from csql_sim.discovery import transition_log
from csql_sim.discovery.induction import Evidence, induce_action
from csql_sim.jobs.discover import discover

N = 3


def legal_pairs():
    out = []
    for s in all_states(N):
        for k, a in enumerate(all_actions(N)):
            if is_legal(s, a):
                out.append((format_state_message(s, 0), k, format_state_message(successor(s, a), 0)))
    return out


class Induction:
    name = "rule induction (this project)"

    def __init__(self):
        self.ev = Evidence(N)
        self.seconds = 0.0

    def learn(self, t):
        began = time.process_time()
        self.ev.add(t)
        self.seconds += time.process_time() - began

    def rules(self):
        return {a: induce_action(self.ev, a) for a in self.ev.outcomes}

    def score(self, pairs, messages):
        began = time.process_time()
        rules = self.rules()
        self.seconds += time.process_time() - began
        right = 0
        for before, k, after in pairs:
            got = rules.get(messages[k])
            if got is None or got.precondition is None or got.add_delete is None:
                continue
            posted = self.ev.posted(before, messages[k])
            right += matches(got.precondition.condition, before) and got.add_delete.apply(posted) == after
        return right

    def count(self):
        return sum((r.precondition is not None) + (r.add_delete is not None) for r in self.rules().values())


class Acs2:
    name = "ACS2 (pyalcs)"

    def __init__(self, length):
        from lcs.agents.acs2 import ClassifiersList, Configuration

        self.cfg = Configuration(classifier_length=length, number_of_possible_actions=len(all_actions(N)),
                                 do_ga=False)
        self.population = ClassifiersList()
        self.t = 0
        self.seconds = 0.0

    def learn(self, t, k):
        from lcs import Perception
        from lcs.agents.acs2 import ClassifiersList

        began = time.process_time()
        p0, p1 = Perception(list(t.before)), Perception(list(t.after))
        match_set = self.population.form_match_set(p0)
        action_set = match_set.form_action_set(k)
        ClassifiersList.apply_alp(self.population, ClassifiersList(), action_set, p0, k, p1, self.t,
                                  self.cfg.theta_exp, self.cfg)
        self.t += 1
        self.seconds += time.process_time() - began

    def score(self, pairs, messages):
        from lcs import Perception

        right = 0
        for before, k, after in pairs:
            p0 = Perception(list(before))
            cands = [c for c in self.population if c.action == k and c.is_reliable() and c.does_match(p0)]
            if cands:
                best = max(cands, key=lambda c: c.q)
                right += best.does_anticipate_correctly(p0, Perception(list(after)))
        return right

    def count(self):
        return len(self.population), sum(1 for c in self.population if c.is_reliable())


def run(stream, every, passes):
    messages = [format_action_message(a, N) for a in all_actions(N)]
    index = {m: k for k, m in enumerate(messages)}
    pairs = legal_pairs()
    ours, peer = Induction(), Acs2(len(stream[0].before))
    curve = []
    seen = 0
    for _ in range(passes):
        for t in stream:
            ours.learn(t)
            peer.learn(t, index[t.action])
            seen += 1
            if seen % every == 0:
                curve.append({"seen": seen, "induction": ours.score(pairs, messages) / len(pairs),
                              "acs2": peer.score(pairs, messages) / len(pairs)})
    total, reliable = peer.count()
    return {"transitions": len(stream), "passes": passes, "curve": curve,
            "induction": {"rules": ours.count(), "cpu_seconds": round(ours.seconds, 2)},
            "acs2": {"classifiers": total, "reliable": reliable, "cpu_seconds": round(peer.seconds, 2)}}


def plot(results, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(results), figsize=(5.5 * len(results), 4), sharey=True)
    for ax, (label, r) in zip(axes, results.items(), strict=True):
        xs = [p["seen"] for p in r["curve"]]
        ax.plot(xs, [p["induction"] for p in r["curve"]], label="rule induction")
        ax.plot(xs, [p["acs2"] for p in r["curve"]], label="ACS2 (pyalcs)")
        for k in range(1, r["passes"]):
            ax.axvline(k * r["transitions"], color="grey", lw=0.5, ls=":")
        ax.set_title(f"{label} stream ({r['transitions']} transitions, x{r['passes']})")
        ax.set_xlabel("transitions seen")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("share of the 42 legal transitions predicted")
    axes[0].legend(loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--arm-log", help="transition log from 'csql-sim discover --log' (else run it, seed 0)")
    ap.add_argument("--every", type=int, default=25)
    ap.add_argument("--passes", type=int, default=3)
    ap.add_argument("--out", default="docs/discovery_acs2.png")
    ap.add_argument("--json", default="docs/discovery_acs2.json")
    args = ap.parse_args()
    random.seed(0)  # pyalcs draws from the random module
    streams = {"symbolic": discover(N, "symbolic", seed=0).log}
    if args.arm_log:
        n, arm = transition_log.load(args.arm_log)
        assert n == N
    else:
        arm = discover(N, "physical", seed=0).log
    streams["arm"] = arm
    began = time.perf_counter()
    results = {label: run(s, args.every, args.passes) for label, s in streams.items()}
    print(f"wall time of both comparisons: {time.perf_counter() - began:.1f} s (shared machine)")
    for label, r in results.items():
        final = r["curve"][-1]
        first = {k: next((p["seen"] for p in r["curve"] if p[k] == 1.0), None) for k in ("induction", "acs2")}
        print(f"{label}: {r['transitions']} transitions x{r['passes']}; all 42 first at {first}; "
              f"final share {final['induction']:.2f} / {final['acs2']:.2f}; induction {r['induction']}; "
              f"acs2 {r['acs2']}")
        r["all_42_first_at"] = first
    plot(results, args.out)
    with open(args.json, "w", encoding="utf-8") as fh:
        json.dump(results, fh, indent=1)


if __name__ == "__main__":
    main()
