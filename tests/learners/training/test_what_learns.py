"""What learns (issue 29): trials alone touch only what they visit, replay only what they experienced, and the
optimal-pair count is a rollout of every pair."""

import numpy as np
import pytest

from csql_sim.core.model.optimal_pairs import count_optimal_pairs, count_optimal_steps
from csql_sim.core.model.search import distance_matrix
from csql_sim.core.model.transition_table import true_table
from csql_sim.learners.paper.params import ParamsError
from csql_sim.learners.training.tabular import make_learner, train_learner


def _q_by_entry(learner) -> dict[tuple[int, int, int], float]:
    """Every Q-classifier of a reference CS-QL learner as (state, goal, action) -> Q."""
    return {(s, g, a): c.q for (s, g), ms in learner.posted() for c, a in zip(ms.candidates, ms.actions, strict=True)}


def test_trials_alone_change_no_q_value_of_an_unvisited_state_goal():
    learner = make_learner("cs-ql", 3, {"sweep": False}, seed=3, engine="reference")
    learner.train(5)
    learner.sweep()  # off: does nothing
    visited = learner.experience.seen  # [goal, slot]
    lay = learner.experience.layout
    visited_pairs = {(int(lay.state[slot]), g) for g, slot in zip(*np.nonzero(visited), strict=True)}
    assert 0 < len(visited_pairs) < 462
    q = _q_by_entry(learner)  # a (state, goal) without classifiers has Q = q0 everywhere
    assert all(v == learner.params.q0 for (s, g, _a), v in q.items() if (s, g) not in visited_pairs)
    assert any(v != learner.params.q0 for v in q.values())
    # and within visited pairs, only the actions taken changed
    taken = {(int(lay.state[slot]), g, int(lay.action[slot])) for g, slot in zip(*np.nonzero(visited), strict=True)}
    assert all(v == learner.params.q0 for key, v in q.items() if key not in taken)


@pytest.mark.parametrize("hindsight", [False, True])
def test_replay_updates_only_experienced_transitions(hindsight):
    learner = make_learner("cs-ql", 4, {"sweep": False, "replay_ratio": 3.0, "replay_hindsight": hindsight},
                           seed=1, engine="reference")
    learner.train(1)
    before = _q_by_entry(learner)
    lay, seen = learner.experience.layout, learner.experience.seen
    backups = learner.replay()
    assert 0 < backups <= 3.0 * learner.experience.steps
    after = _q_by_entry(learner)
    experienced = {(int(lay.state[slot]), int(lay.action[slot])) for slot in np.flatnonzero(seen.any(axis=0))}
    per_goal = {(int(lay.state[slot]), g, int(lay.action[slot])) for g, slot in zip(*np.nonzero(seen), strict=True)}
    changed = [key for key, v in after.items() if v != before.get(key, learner.params.q0)]
    assert changed
    for s, g, a in changed:
        assert (s, a) in experienced  # never a (state, action) no trial took
        assert hindsight or (s, g, a) in per_goal
    assert learner.experience.pairs() < lay.size  # one trial (and the test task) leaves pairs unexperienced


def test_the_fast_engine_refuses_replay_in_one_line():
    with pytest.raises(ParamsError, match="fast engine does not replay"):
        make_learner("cs-ql", 3, {"replay_ratio": 1.0}, engine="fast")


def _rollout_count(best: np.ndarray, n: int) -> int:
    """Optimal pairs by following the greedy table from every start to every goal on the true table."""
    table, dist = true_table(n), distance_matrix(n)
    count = table.state_count
    good = 0
    for g in range(count):
        for s0 in range(count):
            if s0 == g:
                continue
            s, steps = s0, 0
            while s != g and steps <= count:
                a = best[s * count + g]
                s = table.next_state[s, a] if a >= 0 else -1
                steps += 1
                if s < 0:
                    break
            good += s == g and steps == dist[g, s0]
    return good


def test_the_pair_count_equals_a_rollout_of_every_pair_at_n4():
    learner = make_learner("cs-ql", 4, {"sweep": False}, seed=0)
    learner.train(1500)
    best = learner.greedy_table().best
    pairs, steps = count_optimal_pairs(best, 4), count_optimal_steps(best, 4)
    assert 0 < pairs < 15_500  # a partial table
    assert pairs == _rollout_count(best, 4)
    assert steps > pairs  # the per-step figure over-counts a partial table


def test_the_phases_say_what_each_contributed():
    _, meta = train_learner("cs-ql", 1, seed=0, n=4)
    phases = meta["phases"]
    assert phases["trials"]["trials"] == 1 and phases["trials"]["optimal_pairs"] < 100
    assert phases["sweep"]["sweep"] == "value-iteration" and phases["sweep"]["optimal_pairs"] == 15_500
    assert phases["trials"]["experienced_pairs"] < phases["trials"]["legal_pairs"] == 272
    _, meta = train_learner("cs-ql", 200, seed=0, n=3, params={"sweep": False, "replay_ratio": 4.0})
    assert "sweep" not in meta["phases"] and meta["phases"]["replay"]["backups"] > 0
