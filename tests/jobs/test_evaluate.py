import argparse
import json

import pytest

from csql_sim.cli import OneLineParser
from csql_sim.cli import sim as sim_cli
from csql_sim.core.state.world import all_states
from csql_sim.infra.errors import CsqlError
from csql_sim.jobs.evaluate import (
    EpisodeRunner,
    EpisodeSpec,
    EpisodeSummary,
    evaluate,
    make_specs,
    summarise,
    write_json,
)


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
    assert len(make_specs(3, 462)) == 462
    with pytest.raises(CsqlError, match="more than the 462 start/goal pairs"):
        make_specs(3, 463)
    # --seed chooses the sample, reproducibly
    assert make_specs(3, 5, sample_seed=1) == make_specs(3, 5, sample_seed=1) != make_specs(3, 5)


def test_runner_turns_an_error_into_a_failed_summary():
    from csql_sim.core.model.search import BfsPolicy

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
    assert {"config", "episodes", "successes", "success_rate", "optimal", "mean_sim_seconds_per_action",
            "perturbations", "mismatches", "plan_length", "failures", "runs", "provenance"} <= set(data)
    assert data["optimal"] == 4 and data["perturbations"] == data["mismatches"] == 0
    assert data["legend"] == {"A": "red", "B": "green", "C": "blue"}
    assert report.text().splitlines()[0] == "legend: A = red, B = green, C = blue"
    config = data["config"]
    assert config["rules"] == {"file": None, "sha256": None} and config["blocks"] == 3
    assert (config["perception"], config["perturb"], config["seeds"], config["seed"]) == ("pose", False, 1, 0)
    assert config["version"] == data["provenance"]["version"]
    runs = data["runs"]
    assert len(runs) == 4 and set(runs[0]) >= {"start", "goal", "seed", "success", "reason", "length",
                                                 "optimal_length", "sim_seconds", "mismatches", "perturbations"}
    specs = make_specs(3, 4)
    assert [(r["start"], r["goal"], r["seed"]) for r in runs] == [(t.start, t.goal, t.seed) for t in specs]
    assert all(r["length"] == r["optimal_length"] and r["sim_seconds"] > 0 for r in runs)
    stats = data["plan_length"]
    assert stats["episodes"] == 4 and stats["mean_excess"] == 0
    assert stats["mean_length"] == sum(r["length"] for r in runs) / 4


def test_perturbed_runs_record_events_and_plot(tmp_path):
    from csql_sim.jobs.plots import outcome_matrix, write_evaluation_png

    report = evaluate(3, pairs=6, perturb=True, workers=2, progress=False, seed=3)
    events = [e for r in report.runs for e in r.events]
    assert report.perturbations == len(events) > 0
    assert all(0 <= e.step < r.length for r in report.runs for e in r.events)
    matrix = outcome_matrix(report.runs, 3)
    assert (matrix >= 0).sum() == 6 and (matrix == 2).sum() == report.episodes - report.successes
    png = write_evaluation_png(report, tmp_path / "eval.png")
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


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
    assert capsys.readouterr().out == ""  # JSON instead of the text
    args = p.parse_args(["render", "--start", "A,B,C", "--goal", "BA,C", "--out", str(tmp_path / "v.gif"),
                         "--width", "64", "--height", "48", "--fps", "5", "--workers", "1"])
    assert args.func(args) == 0
    assert (tmp_path / "v.gif").exists()
    printed = capsys.readouterr().out
    assert "reached the goal" in printed and printed.startswith("legend: A = red, B = green, C = blue\n")
    assert json.loads((tmp_path / "v.gif.json").read_text())["video"]["legend"] == {"A": "red", "B": "green",
                                                                                     "C": "blue"}


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


def test_evaluate_exit_status(tmp_path, capsys):
    from csql_sim.core.classifiers.r_classifier import r_classifiers
    from csql_sim.core.files.rulebase import RuleBase, save

    empty = save(tmp_path / "empty.yaml", RuleBase(3, list(r_classifiers(3))))
    p = _parser()
    args = p.parse_args(["evaluate", "--rules", str(empty), "--pairs", "2", "--workers", "1", "--quiet", "--json"])
    assert args.func(args) == 1  # an empty rule base: 0 % success is a failed job
    doc = json.loads(capsys.readouterr().out)
    assert doc["success_rate"] == 0 and doc["status"] == 1
    assert doc["config"]["rules"]["sha256"] == __import__("hashlib").sha256(empty.read_bytes()).hexdigest()
    args = p.parse_args(["evaluate", "--rules", str(empty), "--pairs", "2", "--workers", "1", "--quiet",
                         "--min-success", "0", "--plot", str(tmp_path / "e.png")])
    assert args.func(args) == 0  # 0 % is not below --min-success 0
    assert (tmp_path / "e.png").stat().st_size > 1000
    with pytest.raises(SystemExit):
        p.parse_args(["evaluate", "--min-success", "1.5"])


def test_camera_noise_option():
    p = _parser()
    assert p.parse_args(["evaluate", "--camera-noise", "1.5,4"]).camera_noise == (0.0015, 4.0)
    assert p.parse_args(["evaluate", "--camera-noise", "2"]).camera_noise == (0.002, 0.0)
    assert p.parse_args(["evaluate"]).camera_noise == (0.0, 0.0)
    assert p.parse_args(["render", "--camera-noise", "0,3"]).camera_noise == (0.0, 3.0)
    for bad in ("x", "-1", "1,2,3", "nan", "1,inf"):
        with pytest.raises(SystemExit):
            p.parse_args(["evaluate", "--camera-noise", bad])
    with pytest.raises(CsqlError, match="camera noise depth"):
        evaluate(3, pairs=1, workers=1, progress=False, camera_noise=(-0.001, 0.0))


def test_a_task_that_fails_in_its_worker_is_a_failed_episode(monkeypatch):
    import csql_sim.jobs.evaluate as ev
    from csql_sim.sim.control.physical import SimError

    def broken(spec):
        raise SimError(f"no physics for {spec.start}")

    monkeypatch.setattr(ev, "_run_in_worker", broken)
    report = evaluate(3, pairs=2, workers=1, progress=False)
    assert report.episodes == 2 and report.successes == 0
    assert [f["reason"] for f in report.failures] == [f"SimError: no physics for {spec.start}"
                                                     for spec in ev.make_specs(3, 2)]


def test_a_bug_in_a_worker_task_stops_the_evaluation(monkeypatch):
    import csql_sim.jobs.evaluate as ev

    def buggy(spec):
        return spec.no_such_field

    monkeypatch.setattr(ev, "_run_in_worker", buggy)
    with pytest.raises(AttributeError):
        evaluate(3, pairs=2, workers=1, progress=False)


def test_the_rule_file_is_read_once_and_the_workers_get_the_policy_as_data(tmp_path, monkeypatch):
    import csql_sim.core.policies.loader as loader
    import csql_sim.jobs.evaluate as ev
    from csql_sim.cli import main

    rules = tmp_path / "r.yaml"
    assert main(["train", "--trials", "300", "--out", str(rules), "--quiet"]) == 0
    kwargs = {"pairs": 4, "workers": 2, "progress": False, "rules": str(rules)}
    plain = evaluate(3, **kwargs).to_dict()
    loads = []
    read = loader.read_rule_file
    monkeypatch.setattr(loader, "read_rule_file", lambda *a, **k: loads.append(a) or read(*a, **k))
    map_tasks = ev.map_tasks

    def without_the_file(*args, **kw):  # while the episodes run, no worker could read the rule file
        away = rules.rename(tmp_path / "away.yaml")
        try:
            return map_tasks(*args, **kw)
        finally:
            away.rename(rules)

    monkeypatch.setattr(ev, "map_tasks", without_the_file)
    assert evaluate(3, **kwargs).to_dict() == plain  # the same report, the file read once (by the parent)
    assert len(loads) == 1
    assert plain["episodes"] == 4 and plain["config"]["rules"]["sha256"] is not None


def test_an_evaluation_never_runs_the_policy_of_an_earlier_one(tmp_path):
    from csql_sim.core.classifiers.r_classifier import r_classifiers
    from csql_sim.core.files.rulebase import RuleBase, save

    empty = save(tmp_path / "empty.yaml", RuleBase(3, list(r_classifiers(3))))
    here = {"pairs": 1, "workers": 1, "progress": False}  # one worker: the episodes run in this process
    bfs = evaluate(3, **here).to_dict()["runs"]
    assert bfs[0]["success"]
    assert evaluate(3, **here, rules=str(empty)).successes == 0  # no Q-classifier: no action
    assert evaluate(3, **here).to_dict()["runs"] == bfs  # BFS again, not the empty rule base


@pytest.mark.parametrize("option", [{"perception": "lidar"}, {"camera_noise": (0.0, -1.0)}])
def test_bad_options_are_refused_before_any_episode(monkeypatch, option):
    import csql_sim.jobs.evaluate as ev

    started = []
    monkeypatch.setattr(ev, "map_tasks", lambda *a, **k: started.append(a))
    monkeypatch.setattr(ev, "load_policy", lambda *a, **k: started.append(a))
    with pytest.raises(CsqlError):
        evaluate(3, pairs=2, workers=2, progress=False, **option)
    assert started == []  # refused before the rule file was read or any episode started
