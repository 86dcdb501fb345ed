import tracemalloc

import numpy as np
import pytest

from csql_sim.core.classifiers.classifier_list import ClassifierList
from csql_sim.core.model.pairs import pair_count, rank, sample_ranks, unrank
from csql_sim.core.model.search import distance, true_distances
from csql_sim.core.policies.greedy_table import GreedyTable
from csql_sim.core.policies.policy import QPolicy
from csql_sim.core.policies.rollout import check_pairs
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.world import BlocksWorld
from csql_sim.infra.errors import CsqlError
from csql_sim.jobs.evaluate import make_specs
from csql_sim.learners.training.tabular import train

N6_STATES = 7057


def test_rank_and_unrank_are_inverse_and_start_major():
    every = [(s, g) for s in range(22) for g in range(22) if s != g]
    assert [unrank(r, 22) for r in range(pair_count(22))] == every
    assert all(rank(s, g, 22) == r for r, (s, g) in enumerate(every))
    for r in (0, 1, 49_793_191, 12_345_678):
        assert rank(*unrank(r, N6_STATES), N6_STATES) == r
    with pytest.raises(CsqlError):
        unrank(pair_count(N6_STATES), N6_STATES)


def test_sampling_n6_pairs_is_cheap_and_seeded():
    assert pair_count(N6_STATES) == 49_794_192
    tracemalloc.start()
    ranks = sample_ranks(N6_STATES, 1000, seed=3)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    assert peak < 2_000_000  # a list of all pairs would take gigabytes
    assert len(set(ranks)) == 1000 and ranks == sorted(ranks)
    assert ranks == sample_ranks(N6_STATES, 1000, seed=3) != sample_ranks(N6_STATES, 1000, seed=4)
    assert all(s != g for s, g in (unrank(r, N6_STATES) for r in ranks))


def test_evaluate_specs_for_n6_sample_one_pair():
    specs = make_specs(6, 1, sample_seed=0)
    assert len(specs) == 1
    assert parse_config(specs[0].start, 6) != parse_config(specs[0].goal, 6)
    first = [(s.start, s.goal, s.seed) for s in make_specs(3, 5, seeds=2)[:2]]
    assert first == [("BCA", "AC+B", 248), ("BCA", "AC+B", 249)]  # the sample the enumerating version drew


def test_bfs_plans_for_sampled_n6_pairs_are_optimal():
    results = list(check_pairs(None, 6, 3, seed=1))
    world = BlocksWorld.of(6)
    assert len(results) == 3
    for r in results:
        assert r.optimal
        assert r.optimal_length == distance(world.states[r.start], world.states[r.goal])


def test_greedy_table_answers_as_qpolicy():
    rb = train("cs-ql", 200, seed=5, params={"sweep": False})  # a partial rule base: gaps and ties
    table, q = GreedyTable.from_rulebase(rb), QPolicy(ClassifierList(rb.classifiers), 3)
    world = BlocksWorld.of(3)
    answered = 0
    for g in world.states:
        for s in world.states:
            if s == g:
                continue
            try:
                want = q.act(s, g)
            except CsqlError:
                with pytest.raises(CsqlError):
                    table.act(s, g)
                continue
            assert table.act(s, g) == want
            answered += 1
    assert answered > 100


def test_all_pairs_against_bfs_n3():
    rb = train("cs-ql", 2500, seed=0)
    results = list(check_pairs(GreedyTable.from_rulebase(rb), 3, "all"))
    assert len(results) == 462 and all(r.optimal for r in results)
    assert list(true_distances(3, 12)) == [distance(s, BlocksWorld.of(3).states[12]) for s in BlocksWorld.of(3).states]
    assert np.all(GreedyTable.from_rulebase(rb).best.reshape(22, 22).diagonal() == -1)


def test_test_tasks_are_maximal_pairs():
    from csql_sim.core.model import task as task_module

    for n in (2, 4):
        world = BlocksWorld.of(n)
        t = task_module.test_task(n)
        assert (world.state_index(t.start), world.state_index(t.goal)) == task_module.first_maximal_pair(n)
    world = BlocksWorld.of(4)
    t = task_module.test_task(4)
    assert distance(t.start, t.goal) == 12 == max(true_distances(4, world.state_index(t.goal)))
    assert (task_module.test_task(3).start.notation(), task_module.test_task(3).goal.notation()) == ("CBA", "BAC")


def test_greedy_pass_steps_table():
    from csql_sim.learners.paper.params import GREEDY_PASS_STEPS

    for n in (2, 3, 4):
        count = len(BlocksWorld.of(n).states)
        assert sum(int(true_distances(n, g).sum()) for g in range(count)) == GREEDY_PASS_STEPS[n]
