"""The pytest plugin, run the way a user's test suite runs it (pytester; loaded by its pytest11 entry point)."""

import subprocess
import sys
from pathlib import Path

import pytest

# pytester's in-process runs drop the modules a run imported; numpy's C extension cannot be
# loaded twice in one process, so the simulator is imported here, once, before any run.
import csql_sim.jobs.execute  # noqa: F401
import csql_sim.sim.control.executor  # noqa: F401
from csql_sim.testing.plugin import assert_reached

pytest_plugins = ["pytester"]

PLUGIN = ["-p", "no:cacheprovider"]  # the plugin itself comes from the installed entry point, as for a user
PROBLEMS = Path(__file__).resolve().parents[1] / "data" / "problems"
REBUILD = '["unstack(A,B)", "putdown(A)", "unstack(B,C)", "stack(B,A)", "pickup(C)", "stack(C,B)"]'


def test_a_plan_that_reaches_the_goal_passes(pytester):
    pytester.makepyfile(f"""
        from csql_sim.testing.plugin import assert_reached

        def test_rebuild(arm):
            result = arm.execute({REBUILD}, start="CBA", goal="ABC")
            assert result.reached
            assert_reached(result)
            assert [s.status for s in result.steps] == ["ok"] * 6 and result.final == "ABC"

        def test_ipc_names_a_plan_file_and_a_partial_goal(arm):
            assert arm.execute(["(unstack a b)", "(put-down a)"], start="CBA", goal=["(clear b)"]).reached
            result = arm.execute_problem(r"{PROBLEMS / 'blocks3-02.pddl'}", r"{PROBLEMS / 'blocks3-02.plan'}")
            assert result.reached and len(arm.results) == 2
    """)
    result = pytester.runpytest(*PLUGIN)
    result.assert_outcomes(passed=2)


def test_a_failing_plan_says_which_step_failed_and_what_was_perceived(pytester):
    pytester.makepyfile("""
        import pytest
        from csql_sim.core.files.ipc_plan import PlanError
        from csql_sim.testing.plugin import assert_reached

        def test_bare_assert(arm):
            result = arm.execute(["unstack(A,B)", "putdown(A)"], start="CBA", goal="ABC")
            assert result.reached

        def test_helper(arm):
            assert_reached(arm.execute(["(unstack a b)", "(put-down a)"], start="CBA", goal="ABC"))

        def test_diverged(arm):
            plan = ["unstack(A,B)", "putdown(A)", "unstack(B,C)", "putdown(B)", "pickup(A)", "stack(A,B)",
                    "pickup(C)", "stack(C,A)"]
            assert_reached(arm.execute(plan, start="CBA", goal="BAC", seed=1, perturb=True))

        def test_refused_before_physics(arm):
            with pytest.raises(PlanError, match="line 2: step 2 stack.B,A. is not applicable in CB.A: B is not held"):
                arm.execute(["unstack(A,B)", "stack(B,A)"], start="CBA", goal="ABC")
    """)
    result = pytester.runpytest(*PLUGIN)
    result.assert_outcomes(passed=1, failed=3)
    out = result.stdout.str()
    # the bare assert: the one-line summary pytest prints for `assert result.reached`
    result.stdout.fnmatch_lines(["*where False = <ExecuteResult not reached: the plan ended; the perceived state "
                                 "A,CB does not satisfy (on b a) (on c b); final A,CB>.reached*"])
    # the helper: every step with what was perceived
    result.stdout.fnmatch_lines(["*AssertionError: NOT reached: the plan ended; the perceived state A,CB does not "
                                 "satisfy (on b a) (on c b)*",
                                 "*goal atoms not satisfied by the perceived state A,CB: (on b a) (on c b)*",
                                 "*1 line 1   (unstack a b)*unstack(A,B)*ok*perceived CB+A*",
                                 "*2 line 2   (put-down a)*putdown(A)*ok*perceived A,CB*"])
    # a physical failure: the step where perception diverged, and what it saw
    result.stdout.fnmatch_lines(["*failed at step 7 (line 7: pickup(C)): diverged; perceived A,B+C (the plan "
                                 "predicts BA+C)*"])
    assert out.count("csql-sim arm") == 3  # the report section of each failed test that used the arm


def test_loading_the_plugin_imports_nothing_heavy():
    heavy = "('pybullet', 'numpy', 'pddl', 'csql_sim.sim', 'csql_sim.jobs')"
    code = f"import sys, csql_sim.testing.plugin; print(sorted(m for m in {heavy} if m in sys.modules))"
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "[]"


def test_the_plugin_is_installed_as_a_pytest11_entry_point():
    from importlib.metadata import entry_points

    ours = [ep for ep in entry_points(group="pytest11") if ep.value == "csql_sim.testing.plugin"]
    assert len(ours) == 1


# ------------------------------------------------------------------ past ten cubes: the ring (issue 54)
LARGE = PROBLEMS.parent / "large"
LIFTED = Path(__file__).resolve().parents[2] / "assets" / "rules" / "lifted.json"
TWELVE = "A,B,C,D,E,F,G,H,I,J,LK"  # K on L


def test_the_arm_runs_a_plan_file_of_twelve_named_cubes_to_its_partial_goal(arm):
    from csql_sim.core.files.pddl_import import read_problem
    from csql_sim.core.state.notation import parse_config

    result = arm.execute_problem(LARGE / "blocks12-names.pddl", LARGE / "blocks12-names.plan")
    assert_reached(result)
    problem = read_problem(LARGE / "blocks12-names.pddl")
    assert problem.goal.partial and problem.goal.satisfied(parse_config(result.final))
    assert [s.text for s in result.steps][:2] == ["(unstack jade ruby)", "(stack jade x-ray)"]


@pytest.mark.parametrize("source", [{"rules": LIFTED}, {"planner": "gn1"},
                                    {"plan": ["(unstack k l)", "(stack k a)"]}])
def test_the_arm_takes_twelve_cubes_to_a_partial_goal_with_lifted_rules_gn1_or_a_plan(arm, source):
    from csql_sim.core.state.notation import parse_config

    result = arm.execute(source.pop("plan", None), start=TWELVE, goal=["(on k a)", "(ontable l)"], **source)
    assert_reached(result)
    final = parse_config(result.final, 12)
    assert final.support[10] == 0 and final.support[11] == -1 and len(result.steps) == 2  # K on A, L on the table


def test_the_arm_takes_a_partial_goal_and_a_plan_named_past_z(arm):
    """28 cubes: partial goals were read up to 26 objects, and ``unstack(AB,AA)`` was no action."""
    from csql_sim.core.state.notation import parse_config
    from csql_sim.core.state.state import default_names

    names = default_names(28)
    start = ", ".join(names[:26]) + ", AA AB"  # AB on AA
    result = arm.execute(["unstack(AB,AA)", "stack(AB,A)"], start=start, goal=["(on ab a)", "(clear aa)"])
    assert_reached(result)
    assert parse_config(result.final, 28).support[27] == 0 and result.final.startswith("A AB, B")


def test_the_arm_follows_the_builtin_rules_by_name(arm):
    """``rules="builtin"`` names the shipped lifted rules, as ``--rules builtin`` and ``csql_sim.execute`` do."""
    from csql_sim.infra.assets import builtin_rules_path

    result = arm.execute(rules="builtin", start="A,B", goal="AB")
    assert_reached(result)
    assert result.final == "AB" and result.source == {"kind": "rules", "file": str(builtin_rules_path())}
