import pytest

from csql_sim.core.model.search import distance
from csql_sim.core.model.task import Task, test_task
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.world import WorldError


def test_success_is_the_perceived_state_equal_to_the_goal():
    goal = parse_config("BAC")
    assert Task.is_success(parse_config("BAC"), goal)
    assert not Task.is_success(parse_config("CBA"), goal)
    assert not Task.is_success(None, goal)


def test_the_test_task_is_the_papers_for_three_blocks():
    task = test_task(3)
    assert (task.start.notation(), task.goal.notation()) == ("CBA", "BAC")
    assert distance(task.start, task.goal) == 8
    assert test_task(4).n == 4 and test_task(4).start != test_task(4).goal


def test_start_and_goal_must_have_the_same_blocks():
    with pytest.raises(WorldError):
        Task(parse_config("CBA"), parse_config("DCBA"))
