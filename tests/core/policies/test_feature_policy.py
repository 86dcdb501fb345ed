"""Lifted Q-classifiers over generated features: the file read back, bad files refused, the greedy choice."""

import json

import numpy as np
import pytest

from csql_sim.core.features.formulation import load_formulation
from csql_sim.core.features.move_features import Literal, literal_values
from csql_sim.core.policies.feature_policy import FeaturePolicy, dumps_feature_policy
from csql_sim.core.policies.gn1 import Gn1Policy
from csql_sim.core.policies.lifted_classifier import LiftedPolicyError, LiftedQClassifier
from csql_sim.core.policies.loader import load_policy, loads_lifted_file
from csql_sim.core.policies.relational_rollout import rollout_relational
from csql_sim.core.state.moves import Move, after, last_action, pick_action, put_action
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.state_count import sample_pairs
from csql_sim.core.state.world import all_states, successor
from csql_sim.infra.assets import asset_text

WELL_PLACED = "all(star(on),eq(on,on_g))"


def gn1_like(domain: str) -> tuple[list[LiftedQClassifier], tuple[Literal, ...]]:
    """Hand-written classifiers over generated literals: the constructive move, else a misplaced block down.

    With a hand, a held block whose goal is the table has ``on = on_g`` (both empty): the third
    literal, ?x held, keeps it from counting as placed.
    """
    literals = (Literal(WELL_PLACED, "x'"), Literal(WELL_PLACED, "x"), Literal("clear", "x"))
    classifiers = [LiftedQClassifier("1##", "block", 0.0), LiftedQClassifier("0##", "block", 3.0),
                   LiftedQClassifier("1##", "table", 0.0), LiftedQClassifier("00#", "table", 1.0),
                   LiftedQClassifier("010", "table", 1.0), LiftedQClassifier("011", "table", 4.0)]
    return classifiers, literals


@pytest.mark.parametrize("name", ["4op", "move"])
def test_a_file_reads_back_and_plans_every_pair(tmp_path, name):
    classifiers, literals = gn1_like(name)
    domain = asset_text("domains", f"blocks-{name}.pddl")
    path = tmp_path / "f.json"
    path.write_text(dumps_feature_policy(classifiers, literals, domain, name, {"seed": 1}))
    policy = load_policy(path)
    assert isinstance(policy, FeaturePolicy) and policy.literals == literals
    assert [c.text() for c in policy.classifiers] == [c.text() for c in classifiers]
    assert json.loads(path.read_text())["atoms"] == [f"x':{WELL_PLACED}", f"x:{WELL_PLACED}", "x:clear"]
    import numpy as np

    for start, goal in sample_pairs(8, 30, np.random.default_rng(2)):
        run = rollout_relational(policy, start, goal, hand=load_formulation(name).hand)
        gn1 = rollout_relational(Gn1Policy(), start, goal)
        assert run.reached and run.length <= gn1.length + 2 * 8


def test_only_the_literals_some_classifier_tests_are_kept(tmp_path):
    classifiers, literals = gn1_like("4op")
    extra = (*literals, Literal("clear", "d"))
    widened = [LiftedQClassifier(c.condition + "#", c.kind, c.advantage) for c in classifiers]
    doc = json.loads(dumps_feature_policy(widened, extra, asset_text("domains", "blocks-4op.pddl"), "4op", {}))
    assert len(doc["atoms"]) == 3 and all(len(line.split()[1]) == 3 for line in doc["classifiers"])


def test_literal_values_read_well_placed_after_the_move():
    form = load_formulation("4op")
    state, goal = parse_config("A,B,C"), parse_config("ABC")
    options, values = literal_values((Literal(WELL_PLACED, "x'"),), form, state, goal)
    constructive = {(m.block, m.onto) for m, v in zip(options, values[:, 0], strict=True) if v}
    assert constructive == {(1, 0)}  # B onto A: the only move after which the moved block is well placed


@pytest.mark.parametrize(("change", "named"), [
    (lambda d: d.update(atoms=["x:some(clear,top)", "x:clear", "x:clear"]), "clear"),
    (lambda d: d.update(atoms=["q:clear", "x:clear", "x:clear"]), "SLOT"),
    (lambda d: d.update(atoms=["x:and(clear", "x:clear", "x:clear"]), "expected"),
    (lambda d: d.update(atoms=["holds:nothere", "x:clear", "x:clear"]), "nothere"),
    (lambda d: d.update(domain="(define (domain x))"), "domain"),
    (lambda d: d.update(classifiers=["Q 1#### move(?x,?d)->block  advantage=0.000 error=0.000 experience=0"]),
     "atoms"),
    (lambda d: d.update(atoms=[f"x:{WELL_PLACED}"] * 600), "literals"),
])
def test_a_bad_file_is_one_error_naming_what_is_wrong(change, named):
    classifiers, literals = gn1_like("4op")
    doc = json.loads(dumps_feature_policy(classifiers, literals, asset_text("domains", "blocks-4op.pddl"), "4op", {}))
    change(doc)
    with pytest.raises(LiftedPolicyError, match=named) as info:
        loads_lifted_file(json.dumps(doc), "f.json")
    assert "\n" not in str(info.value) and "f.json" in str(info.value)


def test_with_a_hand_a_pick_is_followed_by_its_own_moves_put_and_never_undone():
    """Every 4-block state and 6 goals: the pick is the first ranked move's, the put that move's.

    The classifiers rank a block move that places ?x first, then any block move (in move order),
    then the table; no rule against undoing a pick is needed, as the put is the move's own
    (or the one that reaches the goal).
    """
    literals = (Literal(WELL_PLACED, "x'"),)
    classifiers = [LiftedQClassifier("1", "block", 0.0), LiftedQClassifier("0", "block", 0.5),
                   LiftedQClassifier("#", "table", 1.0)]
    policy = FeaturePolicy(classifiers, literals, load_formulation("4op"), asset_text("domains", "blocks-4op.pddl"))
    states = [s for s in all_states(4) if s.held is None]
    goals = [states[int(i)] for i in np.random.default_rng(5).choice(len(states), 6, replace=False)]
    for goal in goals:
        for state in (s for s in states if s != goal):
            first = policy.ranked(state, goal)[0]
            pick = policy.act(state, goal)
            assert pick == pick_action(state, first.block)
            held = successor(state, pick)
            put = successor(held, policy.act(held, goal))
            assert put == (goal if last_action(held, goal) else after(state, first)) and put != state


def test_an_action_that_reaches_the_goal_is_taken():
    """A goal that holds a block ends with its pick; a held block's last put is taken whatever the classifiers say."""
    literals = (Literal("clear", "x"),)
    classifiers = [LiftedQClassifier("#", "table", 0.0), LiftedQClassifier("#", "block", 5.0)]
    policy = FeaturePolicy(classifiers, literals, load_formulation("4op"), asset_text("domains", "blocks-4op.pddl"))
    state = parse_config("ABC")  # C on B on A
    held_goal = successor(state, pick_action(state, 2))
    assert policy.act(state, held_goal) == pick_action(state, 2)
    hand_empty_goal = after(state, Move(2, 1))  # C back on B: the put onto a block, not the table ranked first
    assert policy.act(held_goal, hand_empty_goal) == put_action(Move(2, 1))
    assert policy.act(state, state) is None


def test_the_tie_literal_breaks_ties_between_moves_of_equal_advantage_and_is_read_back():
    """One classifier per kind, so every table move ties: with the tie "the well-placed count rises" first."""
    domain = asset_text("domains", "blocks-move.pddl")
    literals = (Literal("clear", "x"),)
    classifiers = [LiftedQClassifier("#", "table", 0.0), LiftedQClassifier("#", "block", 1.0)]
    tie = Literal(WELL_PLACED, "up")
    plain = FeaturePolicy(classifiers, literals, load_formulation("move"), domain)
    tied = loads_lifted_file(dumps_feature_policy(classifiers, literals, domain, "move", {}, tie), "t.json")
    assert tied.tie == tie and plain.tie is None
    state, goal = parse_config("AB,CD"), parse_config("AB,C,D")  # B on A, D on C; only D's table move places it
    assert [m.block for m in plain.ranked(state, goal)][:2] == [1, 3]  # the two table moves tie
    assert plain.choose(state, goal).block == 1 and tied.choose(state, goal).block == 3
