"""Class 5 of issue 49, and the ``--replay`` overflow of class 1: options refused in one line, exit 2.

``train-lifted --complexity``, ``--domain`` and ``--workers`` without ``--features generated``
(``--workers`` with one population too), and ``plan --optimum-budget`` without a PDDL task,
were silently ignored (exit 0). One rule now covers every command (``cli/args.py``,
``refuse_ignored``: a command names the options its other options make meaningless).
``train --replay 1e308`` passed the finite check and died in an OverflowError; the
parameter's range is bounded ([0, 1e6]) in the one place that declares it.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from hostile_cli import csql, digest


@pytest.mark.parametrize(("argv", "named"), [
    (("train-lifted", "--out", "l.json", "--complexity", 3, "--trials", 2), ("--complexity", "--features generated")),
    (("train-lifted", "--out", "l.json", "--formulation", "move", "--trials", 2),
     ("--formulation", "--features generated")),
    (("train-lifted", "--out", "l.json", "--trials", 2, "--workers", 2), ("--workers", "--features generated")),
    (("train-lifted", "--out", "l.json", "--trials", 2, "--features", "generated", "--committee", 1, "--workers", 2),
     ("--workers", "--committee")),
    (("plan", "--start", "CBA", "--goal", "ABC", "--optimum-budget", 5), ("--optimum-budget", "--problem")),
    (("train", "--blocks", 3, "--out", "t.yaml", "--trials", 20, "--replay", "1e308"), ("--replay", "1e308")),
], ids=["tl-complexity-given", "tl-formulation-given", "tl-workers-without-committee", "tl-workers-committee-1",
        "ob-without-problem", "tr-replay-1e308"])
def test_an_option_that_does_nothing_or_overflows_is_refused(work: Path, argv: tuple, named: tuple) -> None:
    run = csql(work, *argv, timeout=60)
    run.refused(*named)
    assert digest(work) == {}  # nothing written


def test_replay_ratio_in_a_params_file_is_bounded_too(work: Path) -> None:
    (work / "p.yaml").write_text("replay_ratio: 1.0e+300\n")
    csql(work, "train", "--blocks", 3, "--out", "t.yaml", "--trials", 20, "--params", "p.yaml",
         timeout=60).refused("p.yaml", "replay_ratio")
    assert not (work / "t.yaml").exists()


def test_gym_unknown_reset_option_is_a_value_error_naming_it() -> None:
    """gym-n7-options-junk: ``reset(options={"stort": ...})`` was silently ignored."""
    import gymnasium as gym

    import csql_sim.envs  # noqa: F401 - registers the environments

    env = gym.make("csql_sim/BlocksWorld-v0", blocks=7)
    with pytest.raises(ValueError, match="stort"):
        env.reset(options={"stort": "ABCDEFG"})
    observation, _ = env.reset(seed=0, options={"start": "ABCDEFG", "goal": "GFEDCBA"})
    assert observation  # the known keys still work


def test_rp_r_formulation_4op_with_the_move_domain_is_refused(work: Path) -> None:
    from sweep4 import committee, tower_problem

    committee(work, "r.json", formulation="4op")  # the embedded domain is the move domain
    tower_problem(work, "p.pddl", 5)
    csql(work, "plan", "--problem", "p.pddl", "--rules", "r.json", "--optimum-budget", 0, "--plan-out", "o.plan",
         timeout=60).refused("r.json", "formulation", "4op")
    assert not (work / "o.plan").exists()


def test_gen_out_tinyfs_leaves_nothing_in_the_temporary_folder(work: Path, tiny_fs: Path) -> None:
    """gen-out-tinyfs: a full disk is one short line; no copy spills into the temporary folder."""
    run = csql(work, "problems", "--blocks", 1000, "--count", 50, "--out", tiny_fs / "o", timeout=120)
    err = run.refused("No space left")
    assert len(err) < 400
    assert list((work.parent / f"{work.name}-tmp").iterdir()) == []
