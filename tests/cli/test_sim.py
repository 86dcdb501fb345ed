"""``render`` past ten cubes (the ring): a PDDL problem's own names and partial goal, filmed and read back."""

import json
from pathlib import Path

import imageio.v2 as imageio
import pytest

from csql_sim.cli import main
from csql_sim.core.files.pddl_import import read_problem
from csql_sim.core.state.notation import parse_config

ROOT = Path(__file__).resolve().parents[2]
TWELVE = ROOT / "tests" / "data" / "large" / "blocks12-names.pddl"
VIDEO = ["--renderer", "flat", "--width", "96", "--height", "72", "--fps", "6", "--speed", "8", "--workers", "1"]


def _ring(n: int) -> str:
    """n cubes c0..c<n-1> on the table (cubes A.., past Z AA..); the goal: c1 on c0 and the last on the one before."""
    cubes = " ".join(f"c{i}" for i in range(n))
    init = " ".join(f"(ontable c{i}) (clear c{i})" for i in range(n))
    return f"(define (problem ring{n}) (:domain blocks) (:objects {cubes}) (:init (handempty) {init}) " \
           f"(:goal (and (on c1 c0) (on c{n - 1} c{n - 2}))))"


@pytest.mark.parametrize("task, source", [("twelve", []), ("twelve", ["--rules", "builtin"]), ("thirty", [])])
def test_render_a_problem_past_ten_cubes_films_its_partial_goal_in_its_names(tmp_path, capsys, task, source):
    """Default planner past six: gn1; thirty cubes were refused (problems were read up to 26 objects)."""
    problem = TWELVE if task == "twelve" else tmp_path / "ring30.pddl"
    if task == "thirty":
        problem.write_text(_ring(30))
    out, report = tmp_path / "v.mp4", tmp_path / "r.json"
    assert main(["render", "--problem", str(problem), *source, "--out", str(out), *VIDEO, "--json", str(report),
                 "--quiet"]) == 0
    doc, sidecar = json.loads(report.read_text()), json.loads((tmp_path / "v.mp4.json").read_text())
    read = read_problem(problem, max_blocks=30)
    assert doc["reached"] and read.goal.partial and read.goal.satisfied(parse_config(doc["final"], read.n))
    assert doc["source"]["kind"] == ("rules" if source else "gn1")
    assert sidecar["parameters"]["objects"] == read.mapping and list(sidecar["video"]["legend"]) == list(read.objects)
    assert sidecar["video"]["success"] and sidecar["video"]["actions"] == len(doc["steps"])
    assert imageio.get_reader(out).count_frames() == sidecar["video"]["frames"] > 10
    assert all(s["action"].startswith("(") for s in doc["steps"])  # the problem's names, IPC form
