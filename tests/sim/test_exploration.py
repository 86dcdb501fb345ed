import numpy as np

from csql_sim.cli import main
from csql_sim.discovery.explore import Exploration, explore
from csql_sim.jobs.discover import record_discovery
from csql_sim.sim.exploration import ArmWorld


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


def test_render_discovery_writes_a_video(tmp_path, capsys):
    out = tmp_path / "d.gif"
    assert main(["render", "--discovery", "--transitions", "2", "--out", str(out), "--width", "64",
                 "--height", "48", "--fps", "5", "--workers", "1"]) == 0
    assert out.stat().st_size > 0 and "FAILED" in capsys.readouterr().out
