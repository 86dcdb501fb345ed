"""The main job end to end, at a small frame size: learn, prune, Figure 6, arm, video."""

import imageio.v2 as imageio
import pytest

from csql_sim.cli import main
from csql_sim.core.classifiers.classifier_list import ClassifierList
from csql_sim.core.files.rulebase import load
from csql_sim.core.policies.policy import QPolicy
from csql_sim.core.policies.rollout import check_all_pairs


def test_demo_learns_prunes_executes_and_writes_video(tmp_path, capsys):
    code = main(["demo", "--out", str(tmp_path), "--width", "160", "--height", "120", "--fps", "10",
                 "--workers", "1"])
    out = capsys.readouterr().out
    assert code == 0
    assert "goal reached physically: yes" in out
    pruned = load(tmp_path / "pruned.yaml")
    q = [c for c in pruned.classifiers if c.kind == "Q"]
    assert len(q) == 462
    assert all(r.optimal for r in check_all_pairs(QPolicy(ClassifierList(pruned.classifiers), 3), 3))
    assert sum(c.kind == "Q" for c in load(tmp_path / "rules.yaml").classifiers) == 882
    # Figure 6: the test task's eight classifiers, the last one paying off with Q = 1.
    table = [line for line in out.splitlines() if line.startswith("Q  ")]
    assert len(table) == 8 and table[-1].split()[4] == "1.000000"
    reader = imageio.get_reader(tmp_path / "test_task.mp4")
    frame = reader.get_data(0)
    assert frame.shape == (120, 160, 3)
    assert reader.count_frames() > 8 * 5  # eight primitives of most of a simulated second each


def test_demo_takes_blocks(tmp_path, capsys):
    code = main(["demo", "--blocks", "2", "--trials", "100", "--out", str(tmp_path), "--width", "64",
                 "--height", "48", "--fps", "5", "--workers", "1", "--quiet"])
    out = capsys.readouterr().out
    assert code == 0 and "2 blocks" in out and "(AB -> BA)" in out
    assert load(tmp_path / "pruned.yaml").blocks == 2
    assert (tmp_path / "test_task.mp4.json").exists()


@pytest.mark.parametrize(("blocks", "trials"), [(3, 2500), (4, 20000)])
def test_demo_trains_with_the_trials_train_uses_for_n(tmp_path, monkeypatch, blocks, trials):
    """demo --blocks N uses train's per-n default (it trained 2,500 trials at any n)."""
    import csql_sim.learners.training as training

    seen = {}

    def stop(*args, **kwargs):
        seen["trials"] = kwargs["trials"]
        raise KeyboardInterrupt

    monkeypatch.setattr(training, "train", stop)
    assert main(["demo", "--blocks", str(blocks), "--out", str(tmp_path / "out"), "--quiet"]) == 130
    assert seen["trials"] == trials
