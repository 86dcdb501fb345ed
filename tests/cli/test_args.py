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


# ------------------------------------------------------------------ one command grammar (issue 28)
def test_every_help_starts_with_its_description_and_one_example():
    for name, p in _subparsers().items():
        text = p.format_help()
        body = text.split("\n\n", 1)[1]  # after the usage
        assert p.description and body.startswith(p.description.split("\n")[0]), name
        assert "\nexample:\n  csql-sim " + name in text, name


def test_every_blocks_option_states_its_range_and_default():
    import re

    for name, p in _subparsers().items():
        blocks = _options(p).get("--blocks")
        if blocks is not None:
            assert re.search(r"\d+\.\.\d+", blocks.help) and "default" in blocks.help, name


def test_planner_offers_the_same_choices_wherever_plans_are_made():
    subs = _subparsers()
    choices = {name: tuple(_options(subs[name])["--planner"].choices) for name in ("plan", "evaluate", "render",
                                                                                  "execute")}
    assert set(choices.values()) == {("bfs", "rules", "gn1", "gn2")}


def test_every_rule_file_is_read_with_rules():
    subs = _subparsers()
    for name in ("plan", "show", "prune", "evaluate", "render", "execute", "generalize"):
        assert "--rules" in _options(subs[name]), name


def test_deprecated_spellings_work_with_one_warning(tmp_path, capsys):
    from csql_sim.cli import main

    rules = tmp_path / "r.yaml"
    assert main(["train", "--trials", "20", "--out", str(rules), "--quiet"]) == 0
    capsys.readouterr()
    assert main(["show", str(rules)]) == 0
    new = capsys.readouterr()
    assert new.err == ("csql-sim show: warning: the positional RULES is deprecated and goes in 0.3.0; "
                       "use --rules RULES\n")
    assert main(["show", "--rules", str(rules)]) == 0
    assert capsys.readouterr() == (new.out, "")  # the same table, no warning
    assert main(["plan", "--all", "--quiet"]) == 0
    assert capsys.readouterr().err == "csql-sim plan: warning: --all is deprecated and goes in 0.3.0; use --pairs all\n"
    assert main(["show", str(rules), "--rules", str(rules)]) == 2
    assert capsys.readouterr().err.endswith("error: give the rule file once: --rules " + str(rules) +
                                            " or the positional " + str(rules) + ", not both\n")


def test_one_error_prefix(capsys):
    from csql_sim.cli import main

    assert main(["plan", "--start", "CBX", "--goal", "BAC"]) == 2
    assert capsys.readouterr().err.startswith("csql-sim plan: error: ")
    code = None  # a usage error: argparse exits
    try:
        main(["states", "--blocks", "9"])
    except SystemExit as exc:
        code = exc.code
    assert code == 2 and capsys.readouterr().err.startswith("csql-sim states: error: argument --blocks")


def test_execute_video_is_an_alias_of_out(tmp_path, capsys):
    from pathlib import Path

    from csql_sim.cli import main

    problems = Path(__file__).parents[1] / "data" / "problems"
    argv = ["execute", "--problem", str(problems / "blocks3-01.pddl"), "--planner", "gn1", "--quiet"]
    assert main([*argv, "--video", str(tmp_path / "v.gif")]) == 0
    err = capsys.readouterr().err.splitlines()
    assert err[0] == "csql-sim execute: warning: --video is deprecated and goes in 0.3.0; use --out V"
    assert (tmp_path / "v.gif").read_bytes()[:6] == b"GIF89a" and (tmp_path / "v.gif.json").exists()


def test_evaluate_past_six_blocks_samples_twenty_pairs_by_default():
    """Issue 28 item 14: 'evaluate --blocks 8' without --pairs defaulted to 'all' and was refused."""
    from csql_sim.cli.sim_options import check_evaluate_options

    parse = build_parser().parse_args
    large = parse(["evaluate", "--blocks", "8", "--planner", "gn1"])
    check_evaluate_options(large)
    assert (large.pairs, large.seed, large.seeds) == (20, 0, 1)
    small = parse(["evaluate", "--blocks", "4"])
    check_evaluate_options(small)
    assert (small.pairs, small.seed) == ("all", 0)
    given = parse(["evaluate", "--blocks", "8", "--pairs", "3", "--seed", "7"])
    check_evaluate_options(given)
    assert (given.pairs, given.seed) == (3, 7)
