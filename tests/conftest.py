import pytest

from csql_sim.core.notation import parse_config


@pytest.fixture
def task():
    """The paper's test task: A on B on C to C on A on B (8 actions)."""
    return parse_config("CBA"), parse_config("BAC")
