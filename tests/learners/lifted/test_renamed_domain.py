"""The features come from the domain alone: the same domain with every predicate renamed learns the same policy."""

import re

import numpy as np
import pytest

from csql_sim.core.features.formulation import load_formulation, parse_formulation
from csql_sim.core.features.generate import EXTENDED
from csql_sim.core.policies.feature_policy import FeaturePolicy, used_literals
from csql_sim.core.policies.relational_rollout import rollout_relational
from csql_sim.core.state.state_count import sample_pairs
from csql_sim.infra.assets import asset_text
from csql_sim.learners.lifted.generated import GeneratedFeatures
from csql_sim.learners.lifted.learner import learn
from csql_sim.learners.lifted.params import LiftedParams

NEW_NAMES = {"4op": {"on": "rests", "ontable": "grounded", "clear": "free", "handempty": "idle",
                     "holding": "carrying"},
             "move": {"on": "rests", "clear": "free", "block": "thing"}}
DOMAIN_FILES = {"4op": "blocks-4op.pddl", "move": "blocks-move.pddl"}
SMALL = {"features": "generated", "complexity": 5, "trials": 400, "goals": 8, "sizes": (4,), "sweep": 50,
         "min_experience": 20}


def renamed(text: str, names: dict[str, str]) -> str:
    """The domain's text with every predicate renamed (action names and variables as they were)."""
    pattern = re.compile(r"\((" + "|".join(sorted(names, key=len, reverse=True)) + r")(?=[\s)])")
    return pattern.sub(lambda m: "(" + names[m.group(1)], text)


def trained(form, text: str, seed: int):  # noqa: ANN001, ANN201 - a formulation in, a run and a policy out
    params = LiftedParams(**SMALL, grammar="extended")
    vocab = GeneratedFeatures(form, text, params.complexity, params.sample, EXTENDED, params.early)
    run = learn(params, vocab, np.random.default_rng(seed))
    cut, kept = used_literals(run.classifiers, run.literals)
    return run, FeaturePolicy(cut, kept, form, text)


@pytest.mark.slow
@pytest.mark.parametrize("domain", ["4op", "move"])
def test_renaming_every_predicate_learns_the_same_policy(domain):
    """About 10 s of CPU per formulation (two short training runs)."""
    names = NEW_NAMES[domain]
    text = asset_text("domains", DOMAIN_FILES[domain])
    other = renamed(text, names)
    assert all(f"({old} " not in other and f"({old})" not in other for old in names)
    roles = {new: old for old, new in names.items()}
    form = parse_formulation(other, "renamed", "renamed", roles=roles)
    assert [p.name for p in form.predicates] == \
        [names.get(p.name, p.name) if not p.name.endswith("_g") else names[p.name[:-2]] + "_g"
         for p in load_formulation(domain).predicates]
    run, policy = trained(load_formulation(domain), text, 5)
    run_r, policy_r = trained(form, other, 5)
    back = {new: old for old, new in names.items()}
    spelled_back = [re.sub(r"[a-z]+", lambda m: back.get(m.group(0), m.group(0)), lit.text()) for lit in run_r.literals]
    assert spelled_back == [lit.text() for lit in run.literals]  # the same concepts, in the same order
    assert run_r.classifiers == run.classifiers and len(run.classifiers) > 2
    hand = domain == "4op"
    for start, goal in sample_pairs(6, 20, np.random.default_rng(7)):
        if not hand and (start.held is not None or goal.held is not None):
            continue
        a = rollout_relational(policy, start, goal, hand=hand)
        b = rollout_relational(policy_r, start, goal, hand=hand)
        assert a.actions == b.actions and a.reached == b.reached
