"""``csql-sim problems``: seeded, byte-identical per seed, b1..bN, and the --overwrite rule."""

import pytest

from csql_sim.cli import main


def _write(folder, *more):
    return main(["problems", "--blocks", "30,300", "--count", "2", "--seed", "4", "--out", str(folder), *more])


@pytest.mark.parametrize("distribution", ["tall-towers", "uniform"])
def test_problems_are_byte_identical_per_seed_and_differ_across_seeds(tmp_path, distribution):
    more = ["--distribution", distribution]
    assert _write(tmp_path / "a", *more) == 0
    assert _write(tmp_path / "b", *more) == 0
    assert main(["problems", "--blocks", "30,300", "--count", "2", "--seed", "5", "--out", str(tmp_path / "c"),
                 *more]) == 0
    names = sorted(p.name for p in (tmp_path / "a").iterdir())
    assert names == sorted(["domain.pddl", *(f"{distribution}-{n}-0{k}.pddl" for n in (30, 300) for k in (1, 2))])
    for name in names:
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes()
    assert (tmp_path / "a" / names[-1]).read_bytes() != (tmp_path / "c" / names[-1]).read_bytes()
    text = (tmp_path / "a" / names[-1]).read_text()
    assert " b1 " in text and " b300" in text and "b301" not in text


def test_existing_files_need_overwrite(tmp_path, capsys):
    assert _write(tmp_path) == 0
    capsys.readouterr()
    assert _write(tmp_path) == 2
    err = capsys.readouterr().err
    assert "already exists; give --overwrite" in err and err.count("\n") == 1
    assert _write(tmp_path, "--overwrite") == 0


@pytest.mark.parametrize("argv", [["--blocks", "1001"], ["--blocks", "1"], ["--blocks", "25", "--count", "0"],
                                  ["--blocks", "25", "--distribution", "towers"]])
def test_bad_options_are_one_line_and_exit_2(tmp_path, capsys, argv):
    with pytest.raises(SystemExit) as exc:
        main(["problems", *argv, "--out", str(tmp_path / "x")])
    assert exc.value.code == 2
    assert capsys.readouterr().err.strip().count("\n") <= 1 and not (tmp_path / "x").exists()


def test_max_height_files_are_the_same_per_seed_and_their_towers_fit(tmp_path):
    from csql_sim.core.files.pddl_import import read_problem
    from csql_sim.core.model.task_draws import tallest

    for name in ("a", "b"):
        assert main(["problems", "--blocks", "20", "--count", "3", "--max-height", "6", "--seed", "2", "--quiet",
                     "--out", str(tmp_path / name)]) == 0
    for k in (1, 2, 3):
        a, b = (tmp_path / d / f"tall-towers-20-0{k}.pddl" for d in ("a", "b"))
        assert a.read_bytes() == b.read_bytes() and "towers at most 6 high" in a.read_text()
        bp = read_problem(a)
        assert tallest(bp.start) <= 6 and tallest(bp.goal.nearest(bp.start)) <= 6


def test_a_max_height_that_cannot_be_drawn_is_refused_in_one_line_and_nothing_written(tmp_path, capsys):
    code = main(["problems", "--blocks", "30", "--max-height", "3", "--out", str(tmp_path / "p")])
    out, err = capsys.readouterr()
    assert code == 2 and out == "" and err.count("\n") == 1 and "probability" in err, err
    assert not (tmp_path / "p").exists()
