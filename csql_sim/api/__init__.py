"""The library's front door: plan, validate and execute blocks-world PDDL problems; learn lifted rules.

Each function takes a problem as a path or as its PDDL text, and returns a frozen record
in the problem's own names (:mod:`csql_sim.api.results`)::

    import csql_sim

    plan = csql_sim.plan("problem.pddl")              # the shipped lifted rules plan it
    plan.actions                                       # (("unstack", "amber", "pearl"), ...)
    csql_sim.validate("problem.pddl", plan).valid      # True
    csql_sim.execute("problem.pddl", plan, video="run.mp4").reached   # on the simulated arm
    rules = csql_sim.train_lifted(trials=300, out="lifted.json")

The command line calls the same functions (``plan --problem``, ``execute``,
``train-lifted``). Importing :mod:`csql_sim` loads none of this until a name is used, and
nothing here imports the simulator until :func:`execute` runs.
"""

from csql_sim.api.planning import plan, validate
from csql_sim.api.results import Execution, LiftedRules, Plan, Validation
from csql_sim.api.running import execute, train_lifted

__all__ = ["Execution", "LiftedRules", "Plan", "Validation", "execute", "plan", "train_lifted", "validate"]
