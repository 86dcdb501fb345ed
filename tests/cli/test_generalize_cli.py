"""``csql-sim generalize`` end to end: compact, plan every pair, show, prune; bad input is one line."""

import pytest

from csql_sim.cli import main
from csql_sim.core.files.rulebase import load
from csql_sim.infra.provenance import file_sha256


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("generalize")
    rules, out = folder / "rules.npz", folder / "general.yaml"
    assert main(["train", "--out", str(rules), "--quiet"]) == 0
    assert main(["generalize", "--rules", str(rules), "--out", str(out), "--quiet"]) == 0
    return rules, out


def test_generalized_base_records_form_and_input_and_plans_every_pair(files, capsys):
    rules, out = files
    rb = load(out)
    assert rb.meta["form"] == "goal" and rb.meta["source"]["sha256"] == file_sha256(rules)
    assert rb.meta["source"]["form"] == "index" and len(rb.classifiers) <= 40
    code, text, _ = run(capsys, "plan", "--rules", str(out), "--pairs", "all")
    assert code == 0 and "optimal: 462" in text


def test_npz_show_coverage_and_prune(files, capsys, tmp_path):
    rules, _ = files
    npz, pruned = tmp_path / "g.npz", tmp_path / "p.yaml"
    assert run(capsys, "generalize", "--rules", str(rules), "--out", str(npz), "--quiet")[0] == 0
    code, text, _ = run(capsys, "show", "--rules", str(npz))
    lines = text.splitlines()
    assert code == 0 and "Coverage" in lines[0]
    assert sum(int(line.split()[4]) for line in lines[1:]) == 462  # every pair decided by exactly one
    assert run(capsys, "prune", "--rules", str(npz), "--out", str(pruned))[0] == 0
    code, text, _ = run(capsys, "plan", "--rules", str(pruned), "--pairs", "all")
    assert code == 0 and "optimal: 462" in text


def test_malformed_goal_form_rule_file_is_one_line_exit_2(files, capsys, tmp_path):
    _, out = files
    bad = tmp_path / "bad.yaml"
    bad.write_text(out.read_text().replace("condition: S##############G", "condition: S##############X", 1))
    code, _, err = run(capsys, "plan", "--rules", str(bad), "--pairs", "all")
    assert code == 2 and err.count("\n") == 1 and "position 15" in err


def test_generalizing_a_generalized_base_is_refused(files, capsys, tmp_path):
    _, out = files
    code, _, err = run(capsys, "generalize", "--rules", str(out), "--out", str(tmp_path / "x.yaml"))
    assert code == 2 and err.count("\n") == 1 and "goal form" in err


def test_unknown_detector_is_a_usage_error(files, capsys, tmp_path):
    rules, _ = files
    with pytest.raises(SystemExit) as info:
        main(["generalize", "--rules", str(rules), "--out", str(tmp_path / "x.yaml"), "--detectors", "distance"])
    assert info.value.code == 2


@pytest.mark.slow
def test_evaluate_and_render_on_the_arm_follow_a_generalized_base(files, capsys, tmp_path):
    _, out = files
    code, text, _ = run(capsys, "evaluate", "--rules", str(out), "--pairs", "2", "--quiet")
    assert code == 0 and "optimal-length plans among successes: 2/2" in text
    video = tmp_path / "v.gif"
    code, _, _ = run(capsys, "render", "--rules", str(out), "--start", "CBA", "--goal", "BAC", "--out", str(video),
                     "--width", "160", "--height", "120", "--fps", "5", "--quiet")
    assert code == 0 and video.stat().st_size > 0
