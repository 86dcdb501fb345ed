"""Every policy implements the one contract: a name, the blocks it is for, act(state, goal)."""

import inspect

import pytest

from csql_sim.core.model.search import BfsPolicy
from csql_sim.core.policies import policy as policy_module
from csql_sim.core.policies.contract import Policy
from csql_sim.core.policies.default_hierarchy import DefaultHierarchy
from csql_sim.core.policies.gn1 import Gn1Policy
from csql_sim.core.policies.greedy_table import GreedyTable
from csql_sim.core.policies.lifted_policy import LiftedPolicy
from csql_sim.core.policies.policy import QPolicy
from csql_sim.core.policies.sharded_policy import ShardedPolicy

NAMED = [GreedyTable, QPolicy, DefaultHierarchy, ShardedPolicy, LiftedPolicy, Gn1Policy]


@pytest.mark.parametrize("cls", NAMED)
def test_each_policy_names_the_contract_as_its_base(cls):
    assert Policy in cls.__mro__  # named, not only shaped alike
    assert list(inspect.signature(cls.act).parameters) == ["self", "state", "goal"]
    assert isinstance(cls.name, str)


def test_bfs_keeps_it_by_shape_and_a_stranger_does_not():
    assert isinstance(BfsPolicy(), Policy) and Policy not in BfsPolicy.__mro__  # below the policies' layer
    assert list(inspect.signature(BfsPolicy.act).parameters) == ["self", "state", "goal"]

    class NoBlocks:
        name = "x"

        def act(self, state, goal):
            return None

    assert not isinstance(NoBlocks(), Policy)


def test_the_old_name_is_the_contract():
    assert policy_module.Policy is Policy


def test_the_lifted_and_gn1_policies_are_for_any_number_of_blocks():
    assert LiftedPolicy([]).blocks is None and Gn1Policy().blocks is None
    assert (LiftedPolicy([]).name, Gn1Policy().name, BfsPolicy().name) == ("rules", "gn1", "bfs")
