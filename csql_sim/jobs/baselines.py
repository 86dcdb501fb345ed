"""The named baselines of ``--planner``: hand-written lifted policies, yardsticks and not learners.

* ``gn1``: Gupta and Nau's rules (:class:`csql_sim.core.policies.gn1.Gn1Policy`);
* ``gn2``: Slaney and Thiébaux's refinement of them (:class:`csql_sim.core.policies.gn2.Gn2Policy`).

Both plan any number of blocks. Every command that takes ``--planner gn1`` takes ``gn2``.
"""

from __future__ import annotations

from csql_sim.core.policies.contract import Policy
from csql_sim.core.policies.gn1 import Gn1Policy
from csql_sim.core.policies.gn2 import Gn2Policy

NAMED_POLICIES: dict[str, type[Policy]] = {"gn1": Gn1Policy, "gn2": Gn2Policy}
"""Baseline policies by name (``--planner gn1|gn2``): lifted, for any number of blocks."""
