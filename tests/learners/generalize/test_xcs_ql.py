"""XCS-QL: CS-QL's critic plus an XCS-style population; its condensed base plans every pair optimally."""

import numpy as np
import pytest

from csql_sim.core.files.rulebase import save
from csql_sim.core.model.search import count_optimal_greedy
from csql_sim.core.policies.default_hierarchy import DefaultHierarchy
from csql_sim.core.policies.loader import load_policy
from csql_sim.core.policies.rollout import check_all_pairs
from csql_sim.learners.generalize.compaction import compact
from csql_sim.learners.generalize.xcs_ql import XCSQL
from csql_sim.learners.paper.params import defaults_for_blocks, with_overrides
from csql_sim.learners.training.tabular import train


def _learner(seed=0, **overrides):
    return XCSQL(3, with_overrides(defaults_for_blocks("cs-ql", 3), overrides), np.random.default_rng(seed))


@pytest.fixture(scope="module")
def trained():
    learner = _learner()
    learner.train(2500)
    learner.sweep()
    return learner


def test_n3_every_pair_optimal_and_at_most_twice_the_offline_compaction(trained):
    rb = trained.rulebase({"method": "xcs-ql"})
    hierarchy = DefaultHierarchy.from_rulebase(rb)
    plans = check_all_pairs(hierarchy, 3)  # the match set and first-classifier rule, against BFS
    assert len(plans) == 462 and all(p.optimal for p in plans)
    offline, _ = compact(train("cs-ql", seed=0, n=3, engine="reference"))
    assert len(rb.classifiers) <= 2 * len(offline)
    assert rb.meta["population"] > len(rb.classifiers)  # condensed from a larger population
    assert all("#" in c.condition for c in rb.classifiers)


def test_written_base_is_a_rule_file_like_any_other(trained, tmp_path):
    path = save(tmp_path / "xcs.npz", trained.rulebase({"method": "xcs-ql"}))
    assert count_optimal_greedy(load_policy(path, 3).best, 3) == 462
    assert count_optimal_greedy(trained.greedy_table().best, 3) == 462


def test_same_seed_same_population_and_base():
    a, b = _learner(seed=4), _learner(seed=4)
    for learner in (a, b):
        learner.train(200, test_every=0)
        learner.revise()
    assert a.population == b.population
    assert [c.condition for c in a.condensed()] == [c.condition for c in b.condensed()]


def test_after_a_few_trials_the_base_knows_only_what_it_learned():
    learner = _learner(sweep=False)
    learner.train(20, test_every=0)
    learner.revise()
    assert 0 < learner.visited.sum() < 462
    assert count_optimal_greedy(learner.greedy_table().best, 3) < 462
