"""Options silently ignored, and errors that blame the wrong thing (issue 27, class 6).

``evaluate --camera-noise`` without ``--perception camera`` ran without noise and said
nothing. Every option of ``render`` and ``evaluate`` that another option makes meaningless
is now refused in one line naming the conflict (``cli/sim_options.py``). ``render`` with a
valid 8-block start and a goal naming a ninth block blamed the start; a malformed 7-block
message was named twice in its error.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import pytest
from hostile_cli import csql, digest

from csql_sim.cli import main


def test_ev_noise_without_camera(work: Path) -> None:
    run = csql(work, "evaluate", "--quiet", "--blocks", "8", "--planner", "gn1", "--pairs", "1",
               "--camera-noise", "1.5", timeout=60)
    run.refused("--camera-noise", "--perception")
    assert run.stdout == "" and digest(work) == {}


def test_rd_same_start_goal_n8(work: Path) -> None:
    run = csql(work, "render", "--quiet", "--start", "ABCDEFGH", "--goal", "ABCDEFGI", "--planner", "gn1",
               timeout=60)
    err = run.refused("ABCDEFGI", "I")  # the goal, and its block that is not one of A..H
    assert "ABCDEFGH" not in err  # not the valid start
    assert digest(work) == {}


MALFORMED_7 = "S000000001_bacdef0_abcdef0"
"""A 7-block large message whose block B stands on itself (position 11)."""


@pytest.mark.parametrize("argv", [
    ["plan", "--start", MALFORMED_7, "--planner", "gn1"],
    ["render", "--start", MALFORMED_7, "--planner", "gn1", "--quiet"],
    ["render", "--start", "ABCDEFG", "--goal", MALFORMED_7, "--planner", "gn1", "--quiet"],
], ids=["plan", "render-start", "render-goal"])
def test_a_malformed_7_block_message_is_named_once(work: Path, argv: list[str]) -> None:
    err = csql(work, *argv, timeout=60).refused(MALFORMED_7)
    assert err.count(MALFORMED_7) == 1, err
    assert "ABCDEFG " not in err and "'ABCDEFG'" not in err  # the valid start of render-goal is not blamed


IGNORED = [
    (["render", "--start", "CBA", "--goal", "BAC", "--camera-noise", "2"], ["--camera-noise", "--perception"]),
    (["render", "--discovery", "--perception", "camera", "--camera-noise", "2"], ["--camera-noise", "--discovery"]),
    (["render", "--discovery", "--planner", "gn1"], ["--planner", "--discovery"]),
    (["render", "--start", "CBA", "--goal", "BAC", "--transitions", "5"], ["--transitions", "--discovery"]),
    (["render", "--start", "CBA", "--goal", "BAC", "--blocks", "3"], ["--blocks", "--discovery"]),
    (["evaluate", "--problems", "probs", "--pairs", "2"], ["--pairs", "--problems"]),
    (["evaluate", "--problems", "probs", "--seeds", "2"], ["--seeds", "--problems"]),
    (["evaluate", "--problems", "probs", "--blocks", "4"], ["--blocks", "--problems"]),
    (["evaluate", "--problems", "probs", "--workers", "2"], ["--workers", "--problems"]),
    (["evaluate", "--problems", "probs", "--backend", "ray"], ["--backend", "--problems"]),
    (["evaluate", "--problems", "probs", "--perception", "camera", "--camera-noise", "1"],
     ["--camera-noise", "--problems"]),
    (["evaluate", "--problems", "probs", "--plans", "probs", "--planner", "bfs"], ["--plans", "--planner"]),
    (["evaluate", "--problems", "probs", "--planner", "rules"], ["--planner", "--rules"]),
    (["evaluate", "--seed", "3"], ["--seed", "--pairs"]),
    (["evaluate", "--pairs", "2", "--backend", "ray", "--address", "auto", "--workers", "2"],
     ["--workers", "--address"]),
]


@pytest.mark.parametrize(("argv", "names"), IGNORED, ids=[" ".join(a) for a, _ in IGNORED])
def test_an_option_that_would_be_ignored_is_refused(work: Path, monkeypatch: pytest.MonkeyPatch,
                                                     capsys: pytest.CaptureFixture, argv: list[str],
                                                     names: list[str]) -> None:
    (work / "probs").mkdir()
    monkeypatch.chdir(work)
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1 and err.startswith("csql-sim"), err
    for name in names:
        assert name in err, err
    assert digest(work) == {"probs": "dir"}  # nothing ran, nothing written


def test_options_given_where_they_apply_keep_their_defaults() -> None:
    from csql_sim.cli.sim_options import check_evaluate_options

    plain = argparse.Namespace(problems=None, pairs=None, seeds=None, blocks=None, seed=None, workers=None,
                               address=None, backend="processes", camera_noise=(0.0, 0.0), perception="pose")
    check_evaluate_options(plain)
    assert (plain.pairs, plain.seeds, plain.blocks, plain.seed) == ("all", 1, 3, 0)
    sampled = argparse.Namespace(**{**vars(plain), "pairs": 5, "seed": 4, "seeds": None, "blocks": None,
                                    "perception": "camera", "camera_noise": (0.0015, 4.0)})
    check_evaluate_options(sampled)  # a seeded sample with camera noise: nothing to refuse
    assert (sampled.pairs, sampled.seed, sampled.camera_noise) == (5, 4, (0.0015, 4.0))


def test_evaluate_refuses_camera_noise_without_the_camera(monkeypatch: pytest.MonkeyPatch) -> None:
    """The library refuses it too (``ev-noise-without-camera`` at its root), before any episode."""
    import csql_sim.jobs.evaluate as ev
    from csql_sim.infra.errors import CsqlError

    started: list = []
    monkeypatch.setattr(ev, "map_tasks", lambda *a, **k: started.append(a))
    with pytest.raises(CsqlError):
        ev.evaluate(3, pairs=1, workers=1, progress=False, perception="pose", camera_noise=(0.0015, 0.0))
    assert started == []
