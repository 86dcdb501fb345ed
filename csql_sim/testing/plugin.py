"""A pytest plugin for physical plan tests: the ``arm`` fixture runs plans on the simulated Panda.

A test asks for ``arm`` and executes a plan from a start to a goal; the result says
whether the goal was reached, judged from what the arm's perception saw::

    from csql_sim.testing.plugin import assert_reached

    def test_the_tower_is_rebuilt(arm):
        plan = ["unstack(A,B)", "putdown(A)", "unstack(B,C)", "stack(B,A)", "pickup(C)", "stack(C,B)"]
        result = arm.execute(plan, start="CBA", goal="ABC")
        assert_reached(result)

* ``plan``: a list of actions, csql-sim's names (``"unstack(A,B)"``) or IPC ones
  (``"(unstack a b)"``, objects ``a``, ``b``, ... being cubes A, B, ...), or the path of an
  IPC plan file (as Fast Downward and pyperplan write them); or ``rules=`` a rule base
  (``"builtin"``: the shipped lifted rules, any number of cubes), or
  ``planner="bfs"``, instead;
* ``start``: a configuration (``"CBA"`` is A on B on C); ``goal``: a configuration or a
  list of PDDL atoms (``["(on a b)"]``: a partial goal, any state satisfying it counts);
* ``seed``, ``perception`` (``"pose"`` or ``"camera"``), ``perturb``, ``video`` (a path);
* :meth:`Arm.execute_problem` takes a PDDL problem file (and domain) instead.

A plan that is not applicable is refused before anything moves: ``arm.execute`` raises
:class:`~csql_sim.core.files.ipc_plan.PlanError` naming the step. Failure messages:
``assert result.reached`` shows a one-line summary (the failing step and what was
perceived); :func:`assert_reached` (or ``assert result.reached, result.explain()``) shows
every step; and a failed test that used the fixture gets a report section
``csql-sim arm`` with the explanation of each execution.

The plugin imports only pytest when it loads; csql-sim's simulator (and pybullet) is
imported when a test first executes a plan.
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Sequence
from typing import TYPE_CHECKING, Any

import pytest

if TYPE_CHECKING:
    from csql_sim.jobs.execute_report import ExecuteResult

_ARM = pytest.StashKey["Arm"]()


class Arm:
    """The simulated arm of one test: runs plans and keeps their results.

    Args:
        seed: the default episode seed.
        perception: the default perception mode, ``"pose"`` or ``"camera"``.
        perturb: perturb episodes by default.
    """

    def __init__(self, seed: int = 0, perception: str = "pose", perturb: bool = False) -> None:
        self.seed, self.perception, self.perturb = seed, perception, perturb
        self.results: list[ExecuteResult] = []

    def execute(self, plan: str | os.PathLike | Sequence[str] | None = None, *, start: str, goal: str | Sequence[str],
                rules: str | os.PathLike | None = None, planner: str | None = None, seed: int | None = None,
                perception: str | None = None, perturb: bool | None = None,
                video: str | os.PathLike | None = None) -> ExecuteResult:
        """Run ``plan`` (or ``rules``, or ``planner="bfs"``) from ``start`` to ``goal``; see the module docstring."""
        from csql_sim.jobs.execute import execute_task

        result = execute_task(start, goal, plan=plan, rules=rules, planner=planner, video=video,
                              **self._options(seed, perception, perturb))
        self.results.append(result)
        return result

    def execute_problem(self, problem: str | os.PathLike, plan: str | os.PathLike | Sequence[str] | None = None, *,
                        domain: str | os.PathLike | None = None, rules: str | os.PathLike | None = None,
                        planner: str | None = None, seed: int | None = None, perception: str | None = None,
                        perturb: bool | None = None, video: str | os.PathLike | None = None) -> ExecuteResult:
        """Run a PDDL problem's plan (:func:`csql_sim.jobs.execute.execute_problem`)."""
        from csql_sim.jobs.execute import execute_problem

        result = execute_problem(problem, domain, plan=plan, rules=rules, planner=planner, video=video,
                                 **self._options(seed, perception, perturb))
        self.results.append(result)
        return result

    def _options(self, seed: int | None, perception: str | None, perturb: bool | None) -> dict[str, Any]:
        return {"seed": self.seed if seed is None else seed,
                "perception": self.perception if perception is None else perception,
                "perturb": self.perturb if perturb is None else perturb}


@pytest.fixture
def arm(request: pytest.FixtureRequest) -> Iterator[Arm]:
    """The simulated Panda: ``arm.execute(plan, start=..., goal=...)`` returns an ExecuteResult."""
    robot = Arm()
    request.node.stash[_ARM] = robot
    yield robot


def assert_reached(result: ExecuteResult) -> None:
    """Fail the test unless ``result.reached``, with :meth:`ExecuteResult.explain` as the message."""
    __tracebackhide__ = True
    if not result.reached:
        raise AssertionError(result.explain())


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo) -> Iterator[None]:
    """Add a ``csql-sim arm`` section, every execution explained, to the report of a failed test."""
    outcome = yield
    report = outcome.get_result()
    robot = item.stash.get(_ARM, None)
    if robot is not None and robot.results and report.when == "call" and report.failed:
        report.sections.append(("csql-sim arm", "\n\n".join(r.explain() for r in robot.results)))


__all__ = ["Arm", "arm", "assert_reached"]
