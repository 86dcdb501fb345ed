"""``validate``: one line per error naming the step, exit 0 valid / 1 invalid / 2 bad input."""

import json

from csql_sim.cli import main
from csql_sim.jobs.problems import drawn_problems


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def task(tmp_path, n=12):
    (domain_name, domain_text), (name, text) = drawn_problems("tall-towers", [n], 1, seed=3)
    (tmp_path / domain_name).write_text(domain_text)
    (tmp_path / name).write_text(text)
    return tmp_path / domain_name, tmp_path / name


def test_a_plan_from_plan_validates_and_a_broken_one_names_its_failing_step(capsys, tmp_path):
    domain, problem = task(tmp_path)
    plan = tmp_path / "p.plan"
    assert run(capsys, "plan", "--problem", problem, "--plan-out", plan, "--optimum-budget", "0")[0] == 0
    code, out, err = run(capsys, "validate", "--problem", problem, "--plan", plan, "--domain", domain)
    assert code == 0 and out.startswith("valid: ") and err == ""
    lines = [line for line in plan.read_text().splitlines() if line.startswith("(")]
    broken = tmp_path / "broken.plan"
    broken.write_text("\n".join(lines[1:]) + "\n")  # the first step dropped
    code, out, err = run(capsys, "validate", "--problem", problem, "--plan", broken)
    assert code == 1 and err == ""
    first, last = out.splitlines()
    assert first.startswith(f"step 1 (line 1) {lines[1]}: precondition (") and "fails: " in first
    assert last == f"invalid: 1 error(s) in {broken}"
    code, out, _ = run(capsys, "validate", "--problem", problem, "--plan", broken, "--json")
    doc = json.loads(out)
    assert code == 1 and doc["valid"] is False and doc["applied"] == 0 and doc["errors"] == [first]


def test_bad_input_exits_2_in_one_line(capsys, tmp_path):
    domain, problem = task(tmp_path)
    plan = tmp_path / "p.plan"
    plan.write_text("(pick-up b1)\n(fly b1)\n")
    code, out, err = run(capsys, "validate", "--problem", problem, "--plan", plan, "--domain", domain)
    assert code == 2 and out == "" and err.count("\n") == 1 and "line 2" in err and "fly" in err
    code, out, err = run(capsys, "validate", "--problem", tmp_path / "none.pddl", "--plan", plan)
    assert code == 2 and out == "" and err.count("\n") == 1 and "none.pddl" in err
    code, out, err = run(capsys, "validate", "--problem", problem, "--plan", plan, "--json", plan)
    assert code == 2 and err.count("\n") == 1 and plan.read_text() == "(pick-up b1)\n(fly b1)\n"
