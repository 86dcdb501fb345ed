"""``show`` of a goal-form base: list order, coverage per classifier, the classifiers along one plan."""

from csql_sim.core.files.rulebase import RuleBase
from csql_sim.core.model.search import bfs_plan
from csql_sim.core.state.goal_message import GoalForm
from csql_sim.core.state.notation import parse_state_arg
from csql_sim.learners.generalize.compaction import compact
from csql_sim.learners.paper.coverage import coverage_rows, coverage_table
from csql_sim.learners.training.tabular import train


def test_coverage_sums_to_the_pairs_and_the_path_follows_the_plan():
    qs, _ = compact(train("cs-ql", seed=0, n=3, engine="reference"))
    rb = RuleBase(3, qs, GoalForm(3).meta())
    rows = coverage_rows(rb)
    assert [r["position"] for r in rows] == list(range(1, len(qs) + 1))
    assert sum(r["coverage"] for r in rows) == 462
    start, goal = parse_state_arg("CBA", 3), parse_state_arg("BAC", 3)
    path = coverage_rows(rb, start, goal)
    assert len(path) == len(bfs_plan(start, goal)) == 8  # optimal, one deciding classifier per step
    assert coverage_table(path).splitlines()[0].split()[:5] == ["T", "#", "Condition", "Action", "Coverage"]
