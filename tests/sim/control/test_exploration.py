from dataclasses import replace

import numpy as np

from csql_sim.cli import main
from csql_sim.core.state.notation import parse_action_name
from csql_sim.core.state.world import BLOCK_NAMES, legal_actions
from csql_sim.discovery.explore import Exploration, explore
from csql_sim.jobs.discover import record_discovery
from csql_sim.sim.control.exploration import ArmWorld
from csql_sim.sim.world.config import DEFAULT_CONFIG


def test_arm_exploration_records_refused_attempts_without_motion():
    rng = np.random.default_rng(4)
    with ArmWorld(3, rng) as arm:
        result = explore(arm, rng, Exploration(max_transitions=12))
    assert result.transitions == 12 and result.failed > 0
    for t in result.log:
        if not t.ok:
            assert t.after == t.before  # a refused attempt leaves the scene as it was
    assert result.sim_seconds > 0


def test_a_recorded_discovery_episode_captions_failures():
    result, recording = record_discovery(3, seed=0, transitions=3, fps=10)
    failed = [t for t in result.log if not t.ok]
    captions = {(f.caption.step, f.caption.what) for f in recording.frames}
    assert failed and sum("FAILED (" in what for _, what in captions) == len(failed)


def test_render_discovery_writes_a_video_and_its_provenance(tmp_path, capsys):
    import json

    import imageio.v3 as iio

    out = tmp_path / "d.mp4"  # a GIF writer may merge equal frames; an mp4 keeps every one
    assert main(["render", "--discovery", "--transitions", "2", "--out", str(out), "--width", "64",
                 "--height", "48", "--fps", "5", "--workers", "1"]) == 0
    printed = capsys.readouterr().out
    assert out.stat().st_size > 0 and "FAILED" in printed
    sidecar = json.loads((tmp_path / "d.mp4.json").read_text())
    frames = sum(1 for _ in iio.imiter(out))
    assert sidecar["format"] == "csql-sim video provenance" and sidecar["video"]["frames"] == frames
    assert f"({frames} frames)" in printed and sidecar["parameters"]["transitions"] == 2
    legend = {"A": "red", "B": "green", "C": "blue", "D": "yellow"}
    assert sidecar["video"]["legend"] == dict(list(legend.items())[:sidecar["parameters"]["blocks"]])
    assert printed.startswith("legend: A = red, B = green")


def test_a_putdown_with_no_free_spot_is_a_failure_not_a_refusal():
    # every putdown spot is closer than the clearance to some cube: the table has no free spot
    crowded = replace(DEFAULT_CONFIG, layout=replace(DEFAULT_CONFIG.layout, free_clearance=10.0))
    rng = np.random.default_rng(1)
    with ArmWorld(3, rng, config=crowded) as arm:
        pick = next(a for a in legal_actions(arm.perceive()) if a.is_pick)
        assert arm.attempt(pick).ok
        held = arm.perceive()
        assert held.held == pick.block
        put = arm.attempt(parse_action_name(f"putdown({BLOCK_NAMES[pick.block]})", 3))
        assert not put.ok and put.sim_seconds == 0  # failed before the arm moved ...
        assert not put.refused  # ... yet putdown's precondition (holding) holds: no evidence against it
        assert arm.perceive() == held
        again = arm.attempt(pick)  # the hand is full: the guard refuses, and that is a refusal
        assert not again.ok and again.refused


def test_a_nudged_scene_makes_disturbed_transitions_that_teach_nothing():
    from csql_sim.discovery.induction import Evidence

    rng = np.random.default_rng(0)
    with ArmWorld(3, rng, perturb=True, nudge_probability=1.0) as arm:  # a nudge after every attempt
        result = explore(arm, rng, Exploration(max_transitions=20))
    assert result.disturbed > 0
    changed = [t for t in result.log if t.is_refusal and t.after != t.before]  # refused, yet a cube moved
    assert changed
    evidence = Evidence(3)
    assert all(evidence.add(t) for t in changed)
    assert evidence.disturbed == len(changed) and not evidence.outcomes
