"""A committee of lifted Q-classifier populations over generated features: the greedy policy, and its file.

One training run may learn K populations independently (:func:`csql_sim.learners.lifted.committee.train_committee`:
each from its own generator, spawned from the run's, with its own training worlds and features). Each
member ranks a move by the advantage of its most specific matching classifier, as
:class:`~csql_sim.core.policies.feature_policy.FeaturePolicy` does; :class:`CommitteePolicy` takes the
move of least **mean** advantage over the members (a move that some member matches not ranks after
those every member matches; ties: move order), acting as the feature policy acts. Averaging
populations learned apart is bagging: a literal that one population chose by an accident of five-block
worlds, and that misjudges a situation of twenty blocks, is outvoted by members that chose otherwise.

A committee's file is the lifted Q-classifier format at version 2: the domain's PDDL, the formulation,
``meta``, and ``members``, each with the literals its classifiers test (``atoms``) and its
classifiers. A file of one population is version 1, as before;
:func:`csql_sim.core.policies.loader.loads_lifted_file` reads all.
"""

from __future__ import annotations

import json
from collections.abc import Sequence

import numpy as np

from csql_sim.core.features.move_features import Literal, literal_values
from csql_sim.core.policies.feature_policy import FeaturePolicy, feature_policy_from_doc, used_literals
from csql_sim.core.policies.lifted_classifier import (
    LIFTED_Q_FORMAT,
    LiftedPolicyError,
    LiftedQClassifier,
)
from csql_sim.core.state.moves import Move
from csql_sim.core.state.world import State

COMMITTEE_VERSION = 2
"""The lifted Q-classifier format's version for a committee (``members``)."""
MAX_MEMBERS = 9
"""The most populations a committee may have."""


class CommitteePolicy(FeaturePolicy):
    """Greedy policy of K populations over generated features: least mean advantage (module docstring)."""

    def __init__(self, members: Sequence[FeaturePolicy], meta: dict | None = None) -> None:
        if not 1 <= len(members) <= MAX_MEMBERS:
            raise ValueError(f"a committee has 1..{MAX_MEMBERS} members, got {len(members)}")
        first = members[0]
        super().__init__(first.classifiers, first.literals, first.form, first.domain, meta, first.tie)
        self.members = tuple(members)
        union = tuple(dict.fromkeys(lit for m in self.members for lit in m.literals))
        at = {lit: j for j, lit in enumerate(union)}
        self._union = union
        self._columns = tuple(np.array([at[lit] for lit in m.literals], np.int64) for m in self.members)

    def advantages(self, state: State, goal: State) -> tuple[list[Move], list[float | None]]:
        """The legal moves and each one's mean advantage over the members that match it (None: none does).

        A move that some member does not match gets its mean plus the largest advantage any
        member gave, times the members missing, so that it ranks after the moves all of them match.
        """
        options, values = literal_values(self._union, self.form, state, goal)  # once, for every member
        columns = [m.advantages_of(options, values[:, cols])
                   for m, cols in zip(self.members, self._columns, strict=True)]
        worst = max((a for column in columns for a in column if a is not None), default=0.0)
        out: list[float | None] = []
        for row in zip(*columns, strict=True):
            got = [a for a in row if a is not None]
            missing = len(row) - len(got)
            out.append(None if not got else sum(got) / len(got) + missing * (1.0 + worst))
        return options, out

    def text(self) -> list[str]:
        """Each member's classifiers, after a line naming the member."""
        return [line for k, m in enumerate(self.members, 1) for line in (f"member {k}:", *m.text())]


def dumps_committee(members: Sequence[tuple[Sequence[LiftedQClassifier], tuple[Literal, ...]]],
                    domain: str, formulation: str, meta: dict, tie: Literal | None = None) -> str:
    """The text of a committee's file: per member its classifiers, cut to the literals they test; ``tie`` as one's."""
    docs = []
    for classifiers, literals in members:
        cut, kept = used_literals(classifiers, literals)
        docs.append({"atoms": [lit.text() for lit in kept], "classifiers": [c.text() for c in cut]})
    doc = {"format": LIFTED_Q_FORMAT, "version": COMMITTEE_VERSION, "formulation": formulation, "domain": domain,
           "meta": meta, "members": docs}
    if tie is not None:
        doc["tie"] = tie.text()
    return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"


def committee_from_doc(doc: dict, source: str) -> CommitteePolicy:
    """The policy of a committee's file already read as JSON; LiftedPolicyError naming what is wrong."""
    members = doc.get("members")
    if not isinstance(members, list) or not 1 <= len(members) <= MAX_MEMBERS \
            or not all(isinstance(m, dict) for m in members):
        raise LiftedPolicyError(f"{source}: 'members' must be a list of 1..{MAX_MEMBERS} objects")
    shared = {k: doc.get(k) for k in ("domain", "formulation", "meta", "tie")}
    policies = [feature_policy_from_doc({**shared, "atoms": m.get("atoms"), "classifiers": m.get("classifiers")},
                                        f"{source} member {k}") for k, m in enumerate(members, 1)]
    return CommitteePolicy(policies, policies[0].meta)


__all__ = ["COMMITTEE_VERSION", "MAX_MEMBERS", "CommitteePolicy", "committee_from_doc", "dumps_committee"]
