"""How ``plan`` chooses its policy and writes a plan's steps, in the view of n blocks."""

from __future__ import annotations

import argparse
from collections.abc import Sequence

from csql_sim.cli.args import show_progress
from csql_sim.core.policies.loader import load_policy
from csql_sim.core.policies.policy import Policy
from csql_sim.core.policies.relational_rollout import RelationalPolicy
from csql_sim.core.state.message import action_code, format_action_message
from csql_sim.core.state.relational_message import MAX_LARGE_MESSAGE, format_large_action
from csql_sim.core.state.world import MAX_BLOCKS, Action, action_index
from csql_sim.infra.errors import CsqlError
from csql_sim.jobs.baselines import NAMED_POLICIES


def select_policy(args: argparse.Namespace, n: int | None) -> Policy | RelationalPolicy:
    """The policy of ``--planner`` and ``--rules`` for a job of ``n`` blocks.

    Past six blocks only lifted rules and the named baselines (``gn1``, ``gn2``) plan: :func:`load_policy`
    refuses BFS and ground rule files there.
    """
    planner = check_planner(args)
    if planner in NAMED_POLICIES:
        return NAMED_POLICIES[planner]()
    return load_policy(args.rules if planner == "rules" else None, n, progress=show_progress(args))


def check_planner(args: argparse.Namespace) -> str:
    """The planner of ``--planner`` and ``--rules`` (default: rules with --rules, else bfs); CsqlError on a clash."""
    planner = args.planner or ("rules" if args.rules else "bfs")
    if planner == "rules" and not args.rules:
        raise CsqlError("--planner rules needs --rules FILE")
    if planner != "rules" and args.rules:
        raise CsqlError(f"--planner {planner} does not read --rules {args.rules!r}; give one of them")
    return planner


def plan_steps(actions: Sequence[Action], n: int, names: Sequence[str] | None = None) -> list[dict]:
    """The JSON of a plan: ``{"code", "name", "message"}`` per action, in the view of n blocks.

    Up to six blocks the paper's action code and message; 7..26 the action's index + 1 and
    the relational message; past 26 the index + 1 and no message (``None``). The name is
    csql-sim's (``unstack(A,B)``), or with ``names`` (a problem's objects) the action in
    PDDL form in those names, ``(unstack amber pearl)``, whichever planner made the plan.
    """
    from csql_sim.core.files.ipc_plan import ipc_action

    def name(a: Action) -> str:
        return a.name() if names is None else ipc_action(a, names)

    if n <= MAX_BLOCKS:
        return [{"code": action_code(a, n), "name": name(a), "message": format_action_message(a, n)}
                for a in actions]
    return [{"code": action_index(a, n) + 1, "name": name(a),
             "message": format_large_action(a, n) if n <= MAX_LARGE_MESSAGE else None} for a in actions]
