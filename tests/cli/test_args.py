import argparse
import sys

from csql_sim.cli import build_parser
from csql_sim.cli.args import show_progress
from csql_sim.infra.workers import worker_count

COMMANDS_WITH_PROGRESS = ("plan", "train", "show", "prune", "experiment", "bench", "render", "evaluate", "demo")
COMMANDS_WITH_JSON = ("states", "rules", "plan", "show", "bench", "experiment", "evaluate")


def _subparsers() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(action.choices)


def _options(p: argparse.ArgumentParser) -> dict[str, argparse.Action]:
    return {s: a for a in p._actions for s in a.option_strings}


def test_one_vocabulary_across_commands():
    subs = _subparsers()
    for name in COMMANDS_WITH_PROGRESS:
        opts = _options(subs[name])
        assert opts["--quiet"] is opts["--no-progress"] and opts["--quiet"].dest == "quiet", name
    for name in COMMANDS_WITH_JSON:
        opts = _options(subs[name])
        assert opts["--json"].nargs == "?" and opts["--json"].const == "-", name
    for name in ("experiment", "render", "evaluate", "demo"):
        assert _options(subs[name])["--workers"].default is None, name  # cores capped at the tasks


def test_json_flag_with_and_without_a_file():
    parser = build_parser()
    assert parser.parse_args(["states", "--json"]).json == "-"
    assert parser.parse_args(["states", "--json", "s.json"]).json == "s.json"
    assert parser.parse_args(["states"]).json is None
    assert parser.parse_args(["train", "--out", "r.yaml", "--no-progress"]).quiet is True


def test_progress_only_on_a_terminal_and_not_quiet(monkeypatch):
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True)
    assert show_progress(argparse.Namespace(quiet=False))
    assert not show_progress(argparse.Namespace(quiet=True))
    monkeypatch.setattr(sys.stderr, "isatty", lambda: False)
    assert not show_progress(argparse.Namespace(quiet=False))


def test_default_workers(monkeypatch):
    monkeypatch.setattr("os.cpu_count", lambda: 8)
    assert worker_count(None, 3) == 3 and worker_count(None, 100) == 8 and worker_count(None, 0) == 1
    assert worker_count(5, 30) == 5 and worker_count(5, 2) == 2
