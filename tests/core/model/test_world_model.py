import pytest

from csql_sim.core.classifiers.r_classifier import AddDeleteRule, generate_rules, load_paper_rules
from csql_sim.core.model.world_model import WorldModel, WorldModelError
from csql_sim.core.state.message import format_action_message, format_state_message
from csql_sim.core.state.world import BlocksWorld, legal_actions, successor


def test_the_papers_worked_example():
    model = WorldModel(load_paper_rules(), 3)
    msg = "S0111000ttt0000C"
    assert model.legal_actions(msg) == ("A70000001000at00", "A80000001000bt00", "A90000001000ct00")
    assert model.predict(msg, "A70000001000at00") == "S00110000tt000aC"


@pytest.mark.parametrize("n", [2, 3, 4])
def test_legal_actions_and_predictions_equal_the_world_everywhere(n):
    model = WorldModel.for_blocks(n)
    world = BlocksWorld.of(n)
    for goal in (0, len(world.states) - 1):
        for state in world.states:
            msg = format_state_message(state, goal)
            legal = legal_actions(state)
            assert model.legal_actions(msg) == tuple(format_action_message(a, n) for a in legal)
            for a in legal:
                after = format_state_message(successor(state, a), goal)
                assert model.predict(msg, format_action_message(a, n)) == after
                assert model.predict_state(state, a, goal) == successor(state, a)
                assert model.step(msg, world.action_index(a)) == after


def test_no_or_two_add_delete_rules_is_an_error():
    rules = generate_rules(3)
    model = WorldModel(rules[:18], 3)  # preconditions only
    with pytest.raises(WorldModelError, match="0 add-delete rules"):
        model.predict("S0111000ttt0000C", "A70000001000at00")
    twice = WorldModel([*rules, AddDeleteRule("S7##############", "S00#####0#####a#")], 3)
    with pytest.raises(WorldModelError, match="2 add-delete rules"):
        twice.predict("S0111000ttt0000C", "A70000001000at00")


def test_goal_reading_rules_are_memoized_per_goal():
    # a rule that reads the goal field: predictions must not be shared across goals
    rules = [*generate_rules(3)[:18], AddDeleteRule("S7#############C", "S00#####0#####a#")]
    rules += [r for r in generate_rules(3)[18:] if not r.condition.startswith("S7")]
    model = WorldModel(rules, 3)
    assert model.predict("S0111000ttt0000C", "A70000001000at00") == "S00110000tt000aC"
    with pytest.raises(WorldModelError):
        model.predict("S0111000ttt00000", "A70000001000at00")
