import pytest

from csql_sim.discovery import discover
from csql_sim.rules import load_paper_rules


@pytest.mark.slow
def test_the_arm_discovers_figure_5_string_for_string():
    result = discover(3, "physical", seed=0, perception="pose")
    assert result.stopped == "stable"
    assert [(r.condition, r.action) for r in result.rules] == [(r.condition, r.action) for r in load_paper_rules()]
    assert result.failed > 0 and result.sim_seconds > 0
