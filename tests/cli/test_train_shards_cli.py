"""``train``'s sharded runs and the estimate through the CLI: exit status, one line, nothing written."""

import json

import pytest

from csql_sim.cli import main
from csql_sim.core.files import rulebase_shards as rs


def one_error_line(capsys):
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "Traceback" not in err
    return err


@pytest.mark.parametrize("extra, status", [(["--blocks", "5"], 0), (["--blocks", "6", "--max-memory", "1G"], 2),
                                           (["--blocks", "7"], 2)])
def test_dry_run_says_whether_the_job_fits_and_writes_nothing(tmp_path, capsys, extra, status):
    out = tmp_path / "rules"
    assert main(["train", *extra, "--out", str(out), "--dry-run"]) == status
    captured = capsys.readouterr()
    assert captured.out.startswith("estimate: ") and "peak memory" in captured.out
    assert ("refused" in captured.err) == (status == 2) and len(captured.err.splitlines()) == (status == 2)
    assert not out.exists()


def test_seven_blocks_are_refused_before_any_work(tmp_path, capsys):
    out = tmp_path / "rules7"
    assert main(["train", "--blocks", "7", "--out", str(out), "--quiet"]) == 2
    err = one_error_line(capsys)
    assert "7 blocks" in err and "6 blocks" in err and "generalizes" in err and not out.exists()


def test_six_blocks_under_a_small_memory_limit_are_refused(tmp_path, capsys):
    out = tmp_path / "rules6"
    assert main(["train", "--blocks", "6", "--max-memory", "1G", "--out", str(out), "--quiet"]) == 2
    err = one_error_line(capsys)
    assert "1.0 GB" in err and "--force" in err and not out.exists()


def test_a_sharded_run_writes_a_directory_that_plan_reads(tmp_path, capsys):
    out = tmp_path / "rules4"
    assert main(["train", "--blocks", "4", "--shards", "3", "--trials", "500", "--out", str(out), "--quiet"]) == 0
    assert rs.read_manifest(out)["complete"] is True
    capsys.readouterr()
    assert main(["plan", "--rules", str(out), "--pairs", "50", "--quiet"]) == 0
    assert "pairs: 50  covered: 50  optimal: 50" in capsys.readouterr().out
    shard = out / rs.shard_name(1)
    shard.write_bytes(shard.read_bytes()[:-64] + bytes(64))
    assert main(["plan", "--rules", str(out), "--pairs", "200", "--quiet"]) == 2
    err = one_error_line(capsys)
    assert "shard 1" in err and "corrupt" in err


def test_a_sharded_run_refuses_a_folder_of_other_files_and_rule_suffixes(tmp_path, capsys):
    folder = tmp_path / "mine"
    folder.mkdir()
    (folder / "notes.txt").write_text("keep me")
    assert main(["train", "--blocks", "4", "--shards", "2", "--out", str(folder), "--quiet"]) == 2
    assert "notes.txt" not in one_error_line(capsys) and (folder / "notes.txt").read_text() == "keep me"
    assert main(["train", "--blocks", "4", "--shards", "2", "--out", str(tmp_path / "r.npz"), "--quiet"]) == 2
    assert "directory" in one_error_line(capsys)
    assert main(["train", "--blocks", "4", "--resume", "--out", str(tmp_path / "none"), "--quiet"]) == 2
    assert "--resume" in one_error_line(capsys)


def test_resume_takes_the_options_from_the_directory(tmp_path, capsys):
    out = tmp_path / "rules4"
    assert main(["train", "--blocks", "4", "--shards", "3", "--trials", "400", "--seed", "2", "--out", str(out),
                 "--quiet"]) == 0
    before = {p.name: p.read_bytes() for p in out.iterdir() if p.name != rs.REPORT}
    manifest = rs.read_manifest(out)
    manifest["files"] = manifest["files"][:1]
    manifest["complete"] = False
    rs.write_manifest(out, manifest)
    (out / rs.shard_name(2)).unlink()
    assert main(["plan", "--rules", str(out), "--pairs", "5", "--quiet"]) == 2
    assert "--resume" in one_error_line(capsys)
    assert main(["train", "--resume", "--out", str(out), "--quiet"]) == 0
    assert {p.name: p.read_bytes() for p in out.iterdir() if p.name != rs.REPORT} == before


def test_show_reads_the_greedy_path_of_one_goal(tmp_path, capsys):
    out = tmp_path / "rules4"
    assert main(["train", "--blocks", "4", "--shards", "2", "--trials", "300", "--out", str(out), "--quiet"]) == 0
    capsys.readouterr()
    assert main(["show", "--rules", str(out), "--start", "DCBA", "--goal", "ABCD"]) == 0
    rows = [line for line in capsys.readouterr().out.splitlines() if line.startswith("Q ")]
    assert len(rows) == 8  # one greedy Q-classifier per step of the optimal 8-step plan
    assert main(["show", "--rules", str(out)]) == 2
    assert "--start" in one_error_line(capsys)


def test_bad_options_leave_an_existing_base_alone_and_resume_refuses_other_options(tmp_path, capsys):
    out = tmp_path / "rules4"
    assert main(["train", "--blocks", "4", "--shards", "2", "--trials", "200", "--out", str(out), "--quiet"]) == 0
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    for bad in (["--shards", "100000"], ["--params", str(tmp_path / "missing.yaml")], ["--max-memory", "lots"]):
        assert main(["train", "--blocks", "4", *bad, "--out", str(out), "--quiet"]) == 2
        one_error_line(capsys)
        assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert main(["train", "--resume", "--seed", "5", "--out", str(out), "--quiet"]) == 2
    assert "--seed 0, not 5" in one_error_line(capsys)
    assert main(["train", "--resume", "--out", str(out), "--quiet"]) == 0  # complete: nothing to do, stays complete
    assert rs.read_manifest(out)["complete"] is True
    capsys.readouterr()
    assert main(["plan", "--rules", str(out), "--pairs", "3", "--quiet"]) == 0


def test_a_shard_whose_header_lies_is_refused_even_with_a_matching_checksum(tmp_path, capsys):
    out = tmp_path / "rules4"
    assert main(["train", "--blocks", "4", "--shards", "2", "--trials", "200", "--out", str(out), "--quiet"]) == 0
    shard = out / rs.shard_name(0)
    data = shard.read_bytes()
    head = data[len(rs.MAGIC):].split(b"\n", 1)[0]  # the header's JSON line
    nodes = json.loads(head)["arrays"]["first"][1]
    old, new = f'"first": ["<i8", {nodes},'.encode(), f'"first": ["<i8", {nodes - 1},'.encode()
    assert old in head and len(str(nodes)) == len(str(nodes - 1))
    shard.write_bytes(data.replace(head, head.replace(old, new)))  # one node fewer: consistent, but wrong
    manifest = rs.read_manifest(out)
    manifest["files"][0]["sha256"] = rs.file_sha256(shard)
    rs.write_manifest(out, manifest)
    capsys.readouterr()
    assert main(["plan", "--rules", str(out), "--pairs", "40", "--quiet"]) == 2
    assert "shard 0" in one_error_line(capsys)


def _interrupted(*_args, **_kwargs):
    raise KeyboardInterrupt


def test_an_interrupted_run_says_how_to_go_on_and_resume_only_where_it_can(tmp_path, capsys, monkeypatch):
    import csql_sim.learners.training as shards

    real = shards.train_sharded
    monkeypatch.setattr(shards, "train_sharded", _interrupted)
    out = tmp_path / "rules4"
    args = ["train", "--blocks", "4", "--shards", "3", "--trials", "400", "--out", str(out), "--quiet"]
    assert main(args) == 130  # before any shard: there is nothing to resume
    err = one_error_line(capsys)
    assert "no shard saved" in err and "--resume" not in err
    monkeypatch.setattr(shards, "train_sharded", real)
    assert main(args) == 0  # "start again with the same command"
    manifest = rs.read_manifest(out)
    manifest["files"], manifest["complete"] = manifest["files"][:1], False
    rs.write_manifest(out, manifest)
    monkeypatch.setattr(shards, "train_sharded", _interrupted)
    assert main(["train", "--resume", "--out", str(out), "--quiet"]) == 130
    err = one_error_line(capsys)
    assert "1 of 3 shards saved" in err and err.endswith(f"csql-sim train --resume --out {out}")
    monkeypatch.setattr(shards, "train_sharded", real)
    assert main(["train", "--resume", "--out", str(out), "--quiet"]) == 0
    assert rs.read_manifest(out)["complete"] is True
