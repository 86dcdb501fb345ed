"""The arm's tallest tower: a task whose start, goal or plan needs a taller one is refused before any physics."""

import pytest

from csql_sim.cli import main
from csql_sim.core.model.goal_spec import GoalSpec
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.state import default_names
from csql_sim.infra.errors import CsqlError
from csql_sim.jobs.execute import execute_task
from csql_sim.jobs.problems import task_problem_text
from csql_sim.sim.world import MAX_TOWER_HEIGHT, check_tower_heights, goal_height, tower_height

N = MAX_TOWER_HEIGHT + 2
NAMES = default_names(N)
TALL = " ".join(NAMES[: MAX_TOWER_HEIGHT + 1]) + ", " + NAMES[-1]  # a tower one cube too tall, and a cube
FLAT = ", ".join(NAMES)


def test_heights_of_states_and_partial_goals():
    assert tower_height(parse_config(TALL)) == MAX_TOWER_HEIGHT + 1 and tower_height(parse_config(FLAT)) == 1
    assert tower_height(parse_config("AB,C+D")) == 2
    chain = GoalSpec(5, frozenset({("on", (0, 1)), ("on", (1, 2)), ("on", (3, 4))}))
    assert goal_height(chain) == 3 and goal_height(parse_config("ABC,DE")) == 3


def test_a_start_a_goal_or_a_plan_past_the_limit_is_refused_in_one_line():
    tall, flat = parse_config(TALL), parse_config(FLAT)
    check_tower_heights(flat, parse_config(" ".join(NAMES[:MAX_TOWER_HEIGHT]) + ", " + ", ".join(NAMES[-2:])))
    for start, goal, plan, what in ((tall, flat, (), "start has a tower of"), (flat, tall, (), "goal has"),
                                    (flat, flat, (flat, tall), "plan builds a tower of")):
        with pytest.raises(CsqlError, match=what) as caught:
            check_tower_heights(start, goal, plan)
        assert "\n" not in str(caught.value) and f"at most {MAX_TOWER_HEIGHT}" in str(caught.value)


def test_execute_refuses_a_too_tall_partial_goal_before_any_physics():
    atoms = [f"(on {NAMES[i + 1].lower()} {NAMES[i].lower()})" for i in range(MAX_TOWER_HEIGHT)]
    with pytest.raises(CsqlError, match=f"goal has a tower of {MAX_TOWER_HEIGHT + 1} cubes"):
        execute_task(FLAT, atoms, planner="gn1")


@pytest.mark.parametrize("command", ["execute", "render"])
def test_the_cli_refuses_a_too_tall_start_with_exit_status_2_and_writes_nothing(tmp_path, capsys, monkeypatch,
                                                                               command):
    monkeypatch.chdir(tmp_path)
    if command == "execute":
        problem = tmp_path / "tall.pddl"
        problem.write_text(task_problem_text(parse_config(TALL), parse_config(FLAT)))
        argv = ["execute", "--problem", str(problem), "--planner", "gn1", "--out", "v.mp4", "--json", "r.json"]
    else:
        argv = ["render", "--start", TALL, "--goal", FLAT, "--planner", "gn1", "--out", "v.mp4"]
    before = set(tmp_path.iterdir())
    code = main([*argv, "--quiet"])
    out, err = capsys.readouterr()
    assert code == 2 and out == "" and err.count("\n") == 1 and "Traceback" not in err, err
    assert f"tower of {MAX_TOWER_HEIGHT + 1} cubes" in err
    assert set(tmp_path.iterdir()) == before  # nothing written
