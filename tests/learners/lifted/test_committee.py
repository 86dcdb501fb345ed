"""A committee: K populations learned apart from one seed, member 1 the single run of that seed."""

import os

import numpy as np
import pytest

from csql_sim.core.policies.committee_policy import CommitteePolicy
from csql_sim.learners.lifted.committee import train_committee
from csql_sim.learners.lifted.params import LiftedParams
from csql_sim.learners.lifted.ql import train_lifted
from csql_sim.learners.paper.params import ParamsError

SMALL = {"features": "generated", "domain": "move", "complexity": 4, "trials": 100, "goals": 6, "sizes": (4,),
         "sweep": 50, "min_experience": 20}


def test_member_one_is_the_single_run_and_the_others_the_spawned_generators():
    params = LiftedParams(**SMALL)
    seen = []
    run = train_committee(params, np.random.default_rng(5), 3, progress=lambda done, total: seen.append((done, total)))
    alone = train_lifted(params, np.random.default_rng(5))
    kids = np.random.default_rng(5).spawn(2)
    assert run.members[0].classifiers == alone.classifiers and run.members[0].literals == alone.literals
    for member, kid in zip(run.members[1:], kids, strict=True):
        again = train_lifted(params, kid)
        assert member.classifiers == again.classifiers and member.steps == again.steps
    assert len({m.steps for m in run.members}) > 1  # three different runs, not one run three times
    assert seen == [(50, 300), (100, 300), (150, 300), (200, 300), (250, 300), (300, 300)]
    policy = run.policy({"seed": 5})
    assert isinstance(policy, CommitteePolicy) and len(policy.members) == 3 and policy.meta == {"seed": 5}


@pytest.mark.parametrize(("params", "size"), [(LiftedParams(), 2), (LiftedParams(**SMALL), 0),
                                              (LiftedParams(**SMALL), 10)])
def test_a_committee_of_given_atoms_or_of_a_bad_size_is_refused(params, size):
    with pytest.raises(ParamsError, match="committee"):
        train_committee(params, np.random.default_rng(0), size)


def test_members_trained_in_worker_processes_are_the_members_trained_here(monkeypatch):
    monkeypatch.setattr(os, "cpu_count", lambda: 4)  # two workers even where the machine has one core
    params = LiftedParams(**SMALL)
    seen = []
    here = train_committee(params, np.random.default_rng(7), 3)
    apart = train_committee(params, np.random.default_rng(7), 3, workers=2,
                            progress=lambda done, total: seen.append((done, total)))
    for a, b in zip(here.members, apart.members, strict=True):
        assert a.classifiers == b.classifiers and a.literals == b.literals and a.steps == b.steps
    assert seen == [(100, 300), (200, 300), (300, 300)]  # one report per member finished


def test_workers_must_be_a_positive_integer():
    with pytest.raises(ParamsError, match="workers"):
        train_committee(LiftedParams(**SMALL), np.random.default_rng(0), 2, workers=0)
