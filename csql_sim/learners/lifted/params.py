"""The parameters of LQ-CS (:mod:`csql_sim.learners.lifted.learner`), every one with its default and range."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

from csql_sim.core.state.atom_names import ATOMS
from csql_sim.learners.paper.params import ParamsError

TRAIN_SIZES = (3, 4, 5)
"""The world sizes a lifted learner may train on."""
FEATURES = ("given", "generated")
GRAMMARS = ("base", "extended")
"""The constructor sets of generated features (:class:`LiftedParams` ``grammar``)."""
"""What the lifted classifiers may read."""
READ_ATOMS = tuple(a for a in ATOMS if a != "least-stuck(?x)")
"""The given atoms the classifiers read by default: all but ``least-stuck(?x)`` (:class:`LiftedParams`)."""


@dataclass(frozen=True)
class LiftedParams:
    """Parameters of LQ-CS; every one with its default and range.

    Attributes:
        trials: training trials (one start/goal pair each). Range >= 1; default 3000.
        sizes: world sizes drawn uniformly per trial. Each of 3, 4, 5; default (5,): the largest
            small world has the deadlocks between towers that large worlds are made of.
        goals: training goals per size, drawn once when the size is first met. Range >= 1; default 40,
            and 200 with generated features in the move domain (thousands of features need more
            situations to tell the general ones from the accidents of a few goals; in a domain
            with a hand, six times more literals make the feature table of 200 goals about 5 GB).
        beta: learning rate of the lifted advantages and errors. Range (0, 1]; default 0.02.
        epsilon: probability of a random legal move. Range [0, 1); default 0.5 (spreads the updates).
        tau: moves of advantage that tell two conditions apart. Range > 0; default 0.05 (near-ties
            decide the detours of large worlds, so only conditions that agree closely are merged).
        min_experience: updates before a classifier is split or merged. Range >= 1; default 30
            with the given atoms, 100 with generated features (a split chosen among thousands
            needs more evidence).
        sweep: trials between specialization and generalization sweeps. Range >= 1; default 100 with the
            given atoms, 300 with generated features: their split statistics restart every sweep, so a
            sweep must give both values of a decisive literal ``min_experience`` updates.
        rare_experience: updates on a literal's rarer value for a rare split (gap above ``rare_gap``,
            :func:`~csql_sim.learners.lifted.rules.split_position`). Range 1..``min_experience``; default
            ``min_experience``, none (20 fixed one 4-operator seed and broke two: ``docs/features.md``).
        rare_gap: moves of advantage a rare split needs. Range > ``tau``; default 1.0 (a wasted move).
        replay: whether every sweep also backs up the remembered ground values through the
            world model (:meth:`_Learner.replay`). True or False; default True.
        early: a tie-break's weight, in moves. With ``given``, the cost of a move per block still
            misplaced after it; with ``generated``, per unit of a potential stated over generated
            features, the count fitted to the moves left that value iteration of the reward gives on
            the training world (:mod:`~csql_sim.learners.lifted.potential`), after the move.
            Range [0, 1); default 0.02: too small to trade a move for at five blocks, it prefers,
            among plans of one length, the one that places blocks (or makes the potential fall)
            sooner. 0: no tie-break (generated features then learn from the task's reward alone).
        features: what the classifiers read: ``given`` (hand-written atoms, those of ``atoms``) or
            ``generated`` (features built from the domain's predicates,
            :mod:`~csql_sim.learners.lifted.vocab`). Default ``given``.
        domain: the formulation of ``generated`` features: ``4op``, ``move`` or a PDDL domain
            file (:func:`~csql_sim.core.features.formulation.load_formulation`). Default ``4op``.
        complexity: the grammar's complexity bound K for ``generated``. Range 1..10; default 8.
        grammar: the constructors generated: ``base`` (:data:`~csql_sim.core.features.generate.BASE`)
            or ``extended`` (:data:`~csql_sim.core.features.generate.EXTENDED`: role composition,
            union, restriction and loops too). Default ``base``.
        sample: (state, goal) pairs the generated features are pruned on (with every move of
            each). Range 10..5000; default 200.
        atoms: with ``given``, the atoms the classifiers may read; an atom left out is ``#`` in
            every condition. A non-empty subset of :data:`ATOMS`; default :data:`READ_ATOMS`, all
            but ``least-stuck(?x)``: at five blocks a least-stuck table move outside the ``cover`` is
            as short as a cover move (44% of them waste a move at twelve blocks), so with both
            atoms the seeds ranked them differently; without it every seed prefers the cover.
    """

    trials: int = 3000
    sizes: tuple[int, ...] = (5,)
    goals: int | None = None
    beta: float = 0.02
    epsilon: float = 0.5
    tau: float = 0.05
    min_experience: int | None = None
    sweep: int | None = None
    rare_experience: int | None = None
    rare_gap: float = 1.0
    replay: bool = True
    early: float = 0.02
    features: str = "given"
    domain: str = "4op"
    complexity: int = 8
    grammar: str = "base"
    sample: int = 200
    atoms: tuple[str, ...] = READ_ATOMS

    def __post_init__(self) -> None:
        generated = self.features == "generated"
        if self.goals is None:
            object.__setattr__(self, "goals", 200 if generated and self.domain == "move" else 40)
        if self.sweep is None:
            object.__setattr__(self, "sweep", 300 if generated else 100)
        if self.min_experience is None:
            object.__setattr__(self, "min_experience", 100 if generated else 30)
        if self.rare_experience is None:
            object.__setattr__(self, "rare_experience", self.min_experience)
        checks = {
            "trials": isinstance(self.trials, int) and self.trials >= 1,
            "sizes": bool(self.sizes) and all(isinstance(n, int) and n in TRAIN_SIZES for n in self.sizes),
            "goals": isinstance(self.goals, int) and self.goals >= 1,
            "beta": 0 < self.beta <= 1,
            "epsilon": 0 <= self.epsilon < 1,
            "tau": 0 < self.tau < math.inf,
            "min_experience": isinstance(self.min_experience, int) and self.min_experience >= 1,
            "sweep": isinstance(self.sweep, int) and self.sweep >= 1,
            "rare_experience": isinstance(self.rare_experience, int) and isinstance(self.min_experience, int)
            and 1 <= self.rare_experience <= self.min_experience,
            "rare_gap": isinstance(self.rare_gap, (int, float)) and self.tau < self.rare_gap < math.inf,
            "replay": isinstance(self.replay, bool),
            "early": 0 <= self.early < 1,
            "features": self.features in FEATURES,
            "domain": isinstance(self.domain, str) and bool(self.domain),
            "complexity": isinstance(self.complexity, int) and 1 <= self.complexity <= 10,
            "grammar": self.grammar in GRAMMARS,
            "sample": isinstance(self.sample, int) and 10 <= self.sample <= 5000,
            "atoms": bool(self.atoms) and all(a in ATOMS for a in self.atoms),
        }
        bad = [name for name, ok in checks.items() if not ok]
        if bad:
            raise ParamsError(f"lifted learner parameter {bad[0]}={getattr(self, bad[0])!r} is out of range "
                              "(see LiftedParams)")

    def as_dict(self) -> dict:
        """The parameters as plain values (the generated features' own only when they are used)."""
        own = ("atoms",) if self.features == "generated" else \
            ("features", "domain", "complexity", "grammar", "sample")
        return {f.name: list(v) if isinstance(v := getattr(self, f.name), tuple) else v for f in fields(self)
                if f.name not in own}


__all__ = ["FEATURES", "GRAMMARS", "READ_ATOMS", "TRAIN_SIZES", "LiftedParams"]
