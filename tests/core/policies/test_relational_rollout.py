from csql_sim.core.policies.relational_rollout import rollout_relational
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.world import Action, ActionKind


class Scripted:
    name = "scripted"

    def __init__(self, actions):
        self.actions = list(actions)

    def act(self, state, goal):
        return self.actions.pop(0) if self.actions else None


def test_a_plan_that_reaches_the_goal():
    plan = [Action(ActionKind.UNSTACK, 1, 0), Action(ActionKind.PUTDOWN, 1)]
    run = rollout_relational(Scripted(plan), parse_config("AB"), parse_config("A,B"))
    assert run.reached and run.length == 2 and run.actions == tuple(plan)


def test_loops_illegal_actions_silence_and_the_cap_stop_a_run():
    start, goal = parse_config("AB"), parse_config("BA")
    up, down = Action(ActionKind.UNSTACK, 1, 0), Action(ActionKind.STACK, 1, 0)
    assert "loop" in rollout_relational(Scripted([up, down]), start, goal).reason
    assert not rollout_relational(Scripted([Action(ActionKind.PICKUP, 0)]), start, goal).reached
    assert not rollout_relational(Scripted([]), start, goal).reached
    run = rollout_relational(Scripted([up, Action(ActionKind.PUTDOWN, 1)]), start, goal, cap=1)
    assert not run.reached and run.length is None and len(run.actions) == 1
