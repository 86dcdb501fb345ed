import argparse
import json

import pytest

from csql_sim.cli import OneLineParser
from csql_sim.cli import sim as sim_cli
from csql_sim.errors import CsqlError
from csql_sim.evaluate import EpisodeRunner, EpisodeSpec, EpisodeSummary, evaluate, make_specs, summarise, write_json
from csql_sim.world import all_states


def test_specs():
    assert len(make_specs(3)) == 462
    states = [s.notation() for s in all_states(3)]
    assert make_specs(3)[:2] == [EpisodeSpec(start=states[0], goal=states[1], seed=0),
                                 EpisodeSpec(start=states[0], goal=states[2], seed=1)]
    two = make_specs(3, 5, seeds=2)
    assert len(two) == 10 and [s.seed % 2 for s in two] == [0, 1] * 5
    assert make_specs(3, 5) == make_specs(3, 5)
    with pytest.raises(CsqlError):
        make_specs(3, 0)


def test_runner_turns_an_error_into_a_failed_summary():
    from csql_sim.planner import BfsPolicy

    runner = EpisodeRunner(BfsPolicy(), 3, perturb=False, perception="pose")
    bad = runner.run(EpisodeSpec(start="A,B,C", goal="AB", seed=4))  # goal of another world
    assert bad == EpisodeSummary(start="A,B,C", goal="AB", seed=4, success=False, reason=bad.reason)
    assert "blocks" in bad.reason
    report = summarise([bad])
    assert report.failures == [{"start": "A,B,C", "goal": "AB", "seed": 4, "reason": bad.reason}]


def test_evaluate_json(tmp_path):
    report = evaluate(3, pairs=4, workers=2, progress=False)
    assert report.episodes == 4 and report.success_rate == 1.0
    assert 0 < report.mean_sim_seconds_per_action <= 1.0
    out = write_json(report, tmp_path / "r.json")
    data = json.loads(out.read_text())
    assert set(data) == {"episodes", "successes", "success_rate", "optimal", "mean_sim_seconds_per_action",
                         "failures"}
    assert data["optimal"] == 4


def _parser() -> argparse.ArgumentParser:
    p = OneLineParser(prog="csql-sim")
    sub = p.add_subparsers(dest="command", parser_class=OneLineParser)
    sim_cli.register(sub)
    return p


def test_cli_evaluate_and_render(tmp_path, capsys):
    p = _parser()
    args = p.parse_args(["evaluate", "--pairs", "2", "--workers", "1", "--quiet", "--json", str(tmp_path / "e.json")])
    assert args.func(args) == 0
    assert json.loads((tmp_path / "e.json").read_text())["episodes"] == 2
    args = p.parse_args(["render", "--start", "A,B,C", "--goal", "BA,C", "--out", str(tmp_path / "v.gif"),
                         "--width", "64", "--height", "48", "--fps", "5", "--workers", "1"])
    assert args.func(args) == 0
    assert (tmp_path / "v.gif").exists()
    assert "reached the goal" in capsys.readouterr().out


def test_cli_bad_input_is_csql_error(tmp_path):
    p = _parser()
    args = p.parse_args(["render", "--start", "CBX", "--goal", "BAC", "--out", str(tmp_path / "v.mp4")])
    with pytest.raises(CsqlError):
        args.func(args)
    args = p.parse_args(["render", "--start", "CBA", "--goal", "BAC", "--out", str(tmp_path / "v.avi")])
    with pytest.raises(CsqlError):
        args.func(args)
    with pytest.raises(SystemExit):
        p.parse_args(["evaluate", "--pairs", "some"])
