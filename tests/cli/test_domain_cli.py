import pytest
from pddl import parse_domain, parse_problem

from csql_sim.cli import main
from csql_sim.core.model.search import distance
from csql_sim.core.policies.loader import load_policy
from csql_sim.core.policies.rollout import check_all_pairs
from csql_sim.core.state.notation import parse_config


@pytest.fixture(scope="module")
def discovered(tmp_path_factory):
    path = tmp_path_factory.mktemp("disc") / "rules.yaml"
    assert main(["discover", "--world", "symbolic", "--seed", "5", "--quiet", "--out", str(path)]) == 0
    return path


def test_train_on_discovered_rules_plans_optimally_for_all_462_pairs(discovered, tmp_path):
    out = tmp_path / "trained.yaml"
    assert main(["train", "--domain-rules", str(discovered), "--out", str(out), "--no-progress"]) == 0
    results = check_all_pairs(load_policy(out), 3)
    assert len(results) == 462 and all(r.optimal for r in results)


def test_pddl_of_discovered_rules_parses_back_and_is_solved_optimally(discovered, tmp_path):
    assert main(["pddl", "--domain-rules", str(discovered), "--start", "CBA", "--goal", "BAC", "--out",
                 str(tmp_path / "d")]) == 0
    assert main(["pddl", "--blocks", "3", "--out", str(tmp_path / "given")]) == 0
    text = (tmp_path / "d" / "domain.pddl").read_text()
    assert text == (tmp_path / "given" / "domain.pddl").read_text()  # same world model as Figure 5
    domain = parse_domain(tmp_path / "d" / "domain.pddl")
    problem = parse_problem(tmp_path / "d" / "problem.pddl")
    assert len(domain.actions) == 18 and problem.domain_name == domain.name
    planner = pytest.importorskip("pyperplan.planner")
    plan = planner.search_plan(str(tmp_path / "d" / "domain.pddl"), str(tmp_path / "d" / "problem.pddl"),
                               planner.SEARCHES["bfs"], None)
    assert len(plan) == distance(parse_config("CBA"), parse_config("BAC")) == 8


@pytest.mark.parametrize("argv,needle", [
    (["train", "--method", "lt-ql", "--domain-rules", "RULES", "--out", "OUT"], "has no domain knowledge"),
    (["train", "--blocks", "4", "--domain-rules", "RULES", "--out", "OUT"], "not 4"),
    (["pddl", "--start", "CBA", "--out", "OUT"], "both --start and --goal"),
    (["pddl", "--domain-rules", "nonexistent.yaml", "--out", "OUT"], "nonexistent.yaml"),
])
def test_bad_domain_use_is_one_line_exit_2(discovered, tmp_path, capsys, argv, needle):
    argv = [str(discovered) if a == "RULES" else str(tmp_path / "o") if a == "OUT" else a for a in argv]
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert needle in err and err.count("\n") == 1


@pytest.mark.parametrize("command", ["train", "pddl"])
def test_domain_is_a_deprecated_alias_of_domain_rules_that_warns_in_one_line(capsys, tmp_path, command):
    argv = [command, "--domain", str(tmp_path / "nonexistent.yaml"), "--out", str(tmp_path / "out")]
    assert main(argv) == 2
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 2 and "--domain is deprecated" in err[0] and "use --domain-rules FILE" in err[0]
    assert "nonexistent.yaml" in err[1]  # the alias stored the file where --domain-rules puts it


def test_train_lifted_takes_formulation_and_a_pddl_domain_apart(capsys, tmp_path):
    from csql_sim.cli import build_parser

    parser = build_parser()
    args = parser.parse_args(["train-lifted", "--formulation", "move", "--out", "x.json"])
    assert (args.formulation, args.domain) == ("move", None)
    args = parser.parse_args(["train-lifted", "--domain", "move", "--out", "x.json"])
    err = capsys.readouterr().err.splitlines()
    assert (args.formulation, args.domain) == ("move", None) and len(err) == 1 and "--formulation move" in err[0]
    domain = tmp_path / "d.pddl"
    domain.write_text("(define (domain d))")
    code = main(["train-lifted", "--features", "generated", "--formulation", "4op", "--domain", str(domain),
                 "--out", str(tmp_path / "x.json")])
    assert code == 2 and "not both" in capsys.readouterr().err
