"""PDDL problems and IPC plans read into the blocks world; no physics here."""

from pathlib import Path

import numpy as np
import pytest

from csql_sim.core.classifiers.r_classifier import r_classifiers
from csql_sim.core.files.ipc_plan import PlanError, check_plan, ipc_plan_text, parse_plan, read_plan, write_ipc_plan
from csql_sim.core.files.pddl_export import problem_text as export_problem_text
from csql_sim.core.files.pddl_import import PddlImportError, parse_problem_text, read_problem
from csql_sim.core.model.goal_spec import GoalError, GoalSpec
from csql_sim.core.model.search import bfs_plan
from csql_sim.core.state.notation import parse_config
from csql_sim.core.state.world import State, all_states
from csql_sim.jobs.problems import DOMAIN_TEXT, generate_problem, task_problem_text, write_problem_set

DATA = Path(__file__).resolve().parents[2] / "data" / "problems"
LARGE = DATA.parent / "large"
IPC2000 = """(define (problem BLOCKS-4-0)
(:domain BLOCKS)
(:objects D B A C )
(:INIT (CLEAR C) (CLEAR A) (CLEAR B) (CLEAR D) (ONTABLE C) (ONTABLE A)
 (ONTABLE B) (ONTABLE D) (HANDEMPTY))
(:goal (AND (ON D C) (ON C B) (ON B A)))
)
"""


def problem(init: str, goal: str, objects: str = "a b c") -> str:
    return f"(define (problem p) (:domain blocks) (:objects {objects}) (:init {init}) (:goal {goal}))"


def test_an_ipc2000_problem_in_upper_case_is_read():
    bp = parse_problem_text(IPC2000, domain_text=DOMAIN_TEXT)
    assert bp.objects == ("a", "b", "c", "d") and bp.mapping == {"a": "A", "b": "B", "c": "C", "d": "D"}
    assert bp.start == parse_config("A,B,C,D") and bp.style == "4op"
    assert not bp.goal.partial and bp.goal.states == (parse_config("ABCD"),)


def test_names_are_sorted_with_numbers_as_numbers():
    text = problem("(handempty) (ontable b10) (on b2 b10) (clear b2) (ontable b1) (clear b1)",
                   "(and (on b1 b2))", objects="b10 b2 b1")
    bp = parse_problem_text(text)
    assert bp.objects == ("b1", "b2", "b10") and bp.mapping_text() == "b1 -> A, b2 -> B, b10 -> C"
    assert bp.start == parse_config("A,CB")


def test_a_partial_goal_is_a_set_of_states_and_its_nearest_state():
    bp = parse_problem_text(problem("(handempty) (ontable a) (ontable b) (ontable c) (clear a) (clear b) (clear c)",
                                    "(on a b)"))
    assert bp.goal.partial and len(bp.goal.states) == 4
    assert all(bp.goal.satisfied(s) for s in bp.goal.states)
    assert bp.goal.nearest(bp.start) == parse_config("BA,C")  # two actions away; the first BFS meets
    assert bp.goal.nearest(parse_config("BA,C")) == parse_config("BA,C")
    negated = parse_problem_text(problem("(handempty) (ontable a) (on b a) (on c b) (clear c)",
                                         "(and (clear a) (not (on b a)))"))
    assert negated.goal.text() == "(clear a) (not (on b a))"
    assert negated.goal.satisfied(parse_config("A,B,C")) and not negated.goal.satisfied(parse_config("AB,C"))


def test_the_goal_of_a_state_is_that_state_only():
    for state in all_states(3):
        assert GoalSpec.of_state(state).states == (state,)
    with pytest.raises(GoalError, match="no state"):
        GoalSpec(3, frozenset({("on", (0, 1)), ("on", (1, 0))}))


def test_the_move_variants_imply_an_empty_hand():
    three = problem("(on-table b1) (on b2 b1) (on b3 b2) (clear b3)", "(and (on b1 b2) (on b2 b3))",
                    objects="b1 b2 b3")
    bp = parse_problem_text(three)
    assert bp.style == "move" and bp.start == parse_config("ABC") and bp.goal.states == (parse_config("CBA"),)
    one = "(define (problem q) (:domain bw) (:objects a b c table) (:init (block a) (block b) (block c) " \
          "(on a table) (on b table) (on c a) (clear b) (clear c) (clear table)) (:goal (on a b)))"
    bp = parse_problem_text(one)
    assert bp.objects == ("a", "b", "c") and bp.start == parse_config("AC,B")
    assert all(s.held is None for s in bp.goal.states) and len(bp.goal.states) == 3  # BA,C BAC CBA


@pytest.mark.parametrize("text,needle", [
    (problem("(handempty) (ontable a) (ontable b) (ontable c) (clear a) (clear b) (clear c) (red a)", "(on a b)"),
     "unknown predicate (red a)"),
    (problem("(handempty) (ontable a) (ontable b) (clear a) (clear b)", "(on a b)", objects="a b c"),
     "c is placed nowhere"),
    (problem("(handempty) (ontable a) (on a b) (ontable b) (ontable c) (clear a) (clear b) (clear c)", "(on a b)"),
     "a is in two places"),
    (problem("(handempty) (ontable a) (ontable b) (ontable c) (clear a) (clear b)", "(on a b)"),
     "c is clear but (clear c) is missing"),
    (problem("(handempty) (ontable a) (on b a) (ontable c) (clear a) (clear b) (clear c)", "(on a b)"),
     "a has (clear a) but is not clear"),
    (problem("(handempty) (holding a) (ontable b) (ontable c) (clear b) (clear c)", "(on a b)"),
     "the hand is"),
    (problem("(handempty) (ontable a) (ontable b) (ontable c) (clear a) (clear b) (clear c)",
             "(and (on a b) (on b a))"), "no state of the 3-block world satisfies"),
    (problem("(handempty) (ontable a) (ontable b) (ontable c) (clear a) (clear b) (clear c)",
             "(or (on a b) (on b a))"), "not a PDDL problem"),
    (problem("(handempty) (ontable a) (clear a)", "(ontable a)", objects="a"), "needs at least 2"),
])
def test_unrepresentable_problems_are_refused_in_one_line(text, needle):
    with pytest.raises(PddlImportError) as caught:
        parse_problem_text(text)
    assert needle in str(caught.value) and "\n" not in str(caught.value)


def test_past_six_blocks_the_start_is_relational_and_past_26_refused(tmp_path):
    path = tmp_path / "p8.pddl"
    path.write_text(generate_problem(8, np.random.default_rng(0)))
    bp = read_problem(path)
    assert isinstance(bp.start, State) and bp.n == 8 and bp.mapping["h"] == "H"
    assert not bp.goal.partial and bp.goal.satisfied(bp.goal.states[0]) and not bp.goal.satisfied(bp.start)
    names = " ".join(f"b{i}" for i in range(1, 28))
    on_table = " ".join(f"(ontable b{i}) (clear b{i})" for i in range(1, 28))
    with pytest.raises(PddlImportError, match=r"27 blocks; csql-sim reads at most 26"):
        parse_problem_text(problem(f"(handempty) {on_table}", "(on b1 b2)", names))


def test_names_past_six_blocks_sort_as_numbers_and_keep_their_spelling():
    names = "Red green b10 b2 blue yellow orange pink"
    init = " ".join(f"(ontable {x}) (clear {x})" for x in names.lower().split())
    bp = parse_problem_text(problem(f"(handempty) {init}", "(and (on red b2) (on b10 pink))", names))
    assert bp.objects == ("b2", "b10", "blue", "green", "orange", "pink", "red", "yellow")
    assert bp.goal.partial and bp.goal.count is None
    assert bp.goal.atom_texts() == ["(on b10 pink)", "(on red b2)"]


def test_a_foreign_domain_is_refused():
    foreign = "(define (domain d) (:predicates (at ?x)) (:action fly :parameters (?x) :precondition (at ?x) " \
              ":effect (not (at ?x))))"
    with pytest.raises(PddlImportError, match="fly/1 are not the blocks world's"):
        parse_problem_text(IPC2000, domain_text=foreign)


def test_plan_lines_comments_step_numbers_and_both_names():
    bp = parse_problem_text(IPC2000)
    lines = ["; a comment", "", "0: (UNSTACK a b) [1]", "putdown(A)", "(pick-up b) ; inline", "; cost = 3 (unit cost)"]
    steps = parse_plan(lines, bp.index, bp.n)
    assert [(s.line, [a.name() for a in s.actions]) for s in steps] == [
        (3, ["unstack(A,B)"]), (4, ["putdown(A)"]), (5, ["pickup(B)"])]


def test_moves_become_a_pick_and_a_put():
    bp = parse_problem_text(problem("(on-table b1) (on b2 b1) (on b3 b2) (clear b3)", "(on b1 b2)",
                                    objects="b1 b2 b3 table"))
    steps = parse_plan(["(move-b-to-t b3 b2)", "(move b2 b1 b3)", "(move-t-to-b b1 b2)", "(move b2 b3 table)"],
                       bp.index, bp.n)
    assert [[a.name() for a in s.actions] for s in steps] == [
        ["unstack(C,B)", "putdown(C)"], ["unstack(B,A)", "stack(B,C)"], ["pickup(A)", "stack(A,B)"],
        ["unstack(B,C)", "putdown(B)"]]


@pytest.mark.parametrize("line,needle", [
    ("(unstack a z)", "plan line 2: unknown object 'z'"),
    ("(fly a)", "plan line 2: unknown action 'fly'"),
    ("(stack a)", "plan line 2: stack takes 2 argument(s)"),
    ("(move-b-to-b a a b)", "moves a block from or onto itself"),
    ("stack(A)", "plan line 2: 'stack(A)' is not an action"),
])
def test_unreadable_plan_lines_are_named(line, needle):
    bp = parse_problem_text(IPC2000)
    with pytest.raises(PlanError, match=needle.replace("(", r"\(").replace(")", r"\)")):
        parse_plan(["(pick-up a)", line], bp.index, bp.n)


def test_the_first_inapplicable_step_is_named_with_its_line():
    bp = parse_problem_text(IPC2000)
    steps = parse_plan(["(pick-up a)", "; comment", "(stack a b)", "(unstack b c)"], bp.index, bp.n)
    with pytest.raises(PlanError) as caught:
        check_plan(bp.start, steps, bp.objects, "p.plan")
    assert str(caught.value) == ("p.plan line 4: step 3 (unstack b c) is not applicable in BA,C,D: B is not clear "
                                 "(A is on it)")  # the state's names: the objects as the file writes them
    trace = check_plan(bp.start, steps[:2])
    assert [s.notation() for s in trace] == ["A,B,C,D", "B,C,D+A", "BA,C,D"]
    steps = parse_plan(["(pick-up a)", "(stack a b)", "(pick-up c)", "(stack c b)"], bp.index, bp.n)
    with pytest.raises(PlanError, match="line 4: step 4 .* B is not clear"):
        check_plan(bp.start, steps, bp.objects)
    with pytest.raises(PlanError, match="line 2: step 2 .* the hand is not empty \\(it holds A\\)"):
        check_plan(bp.start, parse_plan(["(pick-up a)", "(unstack d c)"], bp.index, bp.n), bp.objects)
    with pytest.raises(PlanError, match="line 1: step 1 .* D is not on C \\(it is on the table\\)"):
        check_plan(bp.start, parse_plan(["(unstack d c)"], bp.index, bp.n), bp.objects)
    with pytest.raises(PlanError) as caught:
        check_plan(bp.start, parse_plan(["(move-b-to-t d c)"], bp.index, bp.n), bp.objects)
    assert str(caught.value) == ("plan line 1: step 1 (move-b-to-t d c) (its unstack(D,C)) is not applicable in "
                                 "A,B,C,D: D is not on C (it is on the table)")


def test_ipc_plans_round_trip(tmp_path):
    states = all_states(4)
    rng = np.random.default_rng(1)
    index = {c: i for i, c in enumerate("abcd")}
    for _ in range(20):
        start, goal = states[rng.integers(len(states))], states[rng.integers(len(states))]
        plan = bfs_plan(start, goal)
        path = write_ipc_plan(plan, tmp_path / "p.plan")
        assert path.read_text().endswith(f"; cost = {len(plan)} (unit cost)\n")
        steps = read_plan(path, index, 4)
        assert tuple(a for s in steps for a in s.actions) == plan
        assert check_plan(start, steps)[-1] == goal
    assert ipc_plan_text(bfs_plan(parse_config("AB"), parse_config("BA")), names=("x", "y")) == \
        "(unstack y x)\n(put-down y)\n(pick-up x)\n(stack x y)\n; cost = 4 (unit cost)\n"


def test_csql_sims_own_export_reads_back():
    start, goal = parse_config("CBA"), parse_config("BAC")
    bp = parse_problem_text(export_problem_text(r_classifiers(3), start, goal))
    assert (bp.style, bp.start, bp.goal.states) == ("csql", start, (goal,))
    steps = parse_plan(["(unstack_a_b)", "(putdown_a)"], bp.index, bp.n)
    assert [a.name() for s in steps for a in s.actions] == ["unstack(A,B)", "putdown(A)"]


def test_task_problems_read_back():
    bp = parse_problem_text(task_problem_text(parse_config("CBA"), parse_config("A,BC")), domain_text=DOMAIN_TEXT)
    assert bp.start == parse_config("CBA") and bp.goal.states == (parse_config("A,BC"),)


def test_the_test_problems_are_the_generators(tmp_path):
    written = write_problem_set(tmp_path, 2, [3, 4, 5], seed=0)
    assert sorted(p.name for p in written) == sorted(p.name for p in DATA.iterdir())
    for path in written:
        assert path.read_text() == (DATA / path.name).read_text(), path.name
    for plan in DATA.glob("*.plan"):
        bp = read_problem(plan.with_suffix(".pddl"), DATA / "domain.pddl")
        assert bp.goal.satisfied(check_plan(bp.start, read_plan(plan, bp.index, bp.n, bp.actions))[-1])


def test_object_names_sort_as_numbers_without_converting_them():
    from csql_sim.core.files.pddl_import import name_key

    huge = "c" + "9" * 5000  # past Python's 4,300-digit limit for int()
    assert sorted(["b10", "b2", "B1", huge, "a"], key=name_key) == ["a", "B1", "b2", "b10", huge]


def test_a_plan_for_eight_named_blocks_is_checked_relationally_and_refused_with_its_line():
    bp = read_problem(LARGE / "blocks8-names.pddl", DATA / "domain.pddl")
    steps = read_plan(LARGE / "blocks8-names.plan", bp.index, bp.n, bp.actions)
    trace = check_plan(bp.start, steps, bp.objects, "p8.plan")
    assert all(isinstance(s, State) for s in trace) and len(trace) == len(steps) + 1
    assert bp.goal.satisfied(trace[-1]) and not bp.goal.satisfied(trace[-2])
    bad = parse_plan(["(unstack x-ray b10)", "(stack x-ray ruby)"], bp.index, bp.n)
    with pytest.raises(PlanError, match=r"^p8.plan line 2: step 2 \(stack x-ray ruby\) is not applicable in "
                                        r"b2 Ruby jade, b10, Slate amber_1 ivory \+ x-ray: Ruby is not clear "
                                        r"\(jade is on it\)$"):
        check_plan(bp.start, bad, bp.objects, "p8.plan")
    assert ipc_plan_text([steps[0].actions[0]]).splitlines()[0] == "(unstack h c)"
