"""The tutorials run as written: every file they create, every command and every Python block (issue 52).

A tutorial (``docs/tutorial_*.md``) is read as a script, in order:

* a fenced block preceded by ``<!-- file: NAME -->`` is written to NAME;
* a ``bash`` block's lines are commands, run in a shell in the tutorial's folder (the
  installed ``csql-sim`` and ``python`` first on the PATH); each must exit 0 unless the
  block is preceded by ``<!-- exit: N -->``;
* a ``python`` block runs in one namespace shared by the page's blocks;
* a ``text`` block preceded by ``<!-- output -->`` holds lines that the block before it
  printed (each line is looked for in that output);
* a block preceded by ``<!-- not run: why -->`` is not run, only compiled if it is Python
  (the Stable-Baselines3 run, which needs torch).

The arm video of the PDDL tutorial is rendered by the slow run (``-m slow`` in CI); the
fast run executes the same command without ``--out``.
"""

import os
import re
import subprocess
import sys
from contextlib import redirect_stdout
from io import StringIO
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
TUTORIALS = sorted((ROOT / "docs").glob("tutorial_*.md"))
BLOCK = re.compile(r"(?:<!-- (?P<mark>[^>]*?) -->\s*\n)?```(?P<lang>[a-z]*)\n(?P<code>.*?)```", re.S)


def blocks(path):
    """``(mark, language, code)`` of every fenced block of a page, in order."""
    return [(m.group("mark") or "", m.group("lang"), m.group("code")) for m in BLOCK.finditer(path.read_text())]


def _shell(command, folder):
    bin_dir = os.path.dirname(sys.executable)
    env = {**os.environ, "PATH": f"{bin_dir}{os.pathsep}{os.environ.get('PATH', '')}"}
    return subprocess.run(command, shell=True, cwd=folder, capture_output=True, text=True, timeout=900, env=env,
                          check=False)


def run_tutorial(path, folder, video=True):
    """Run one page (module docstring); returns the outputs of its blocks, in order."""
    namespace, outputs, last = {"__name__": "__tutorial__"}, [], ""
    previous = os.getcwd()
    os.chdir(folder)
    try:
        for mark, lang, code in blocks(path):
            if mark.startswith("file: "):
                (folder / mark[len("file: "):].strip()).write_text(code)
            elif mark.startswith("not run"):
                if lang == "python":
                    compile(code, f"{path.name} (not run)", "exec")
            elif mark == "output":
                missing = [line for line in code.splitlines() if line.strip() and line.strip() not in last]
                assert missing == [], f"{path.name}: not printed: {missing}\n--- printed:\n{last}"
            elif lang == "bash":
                last = _run_commands(path, code, folder, mark, video)
            elif lang == "python":
                out = StringIO()
                with redirect_stdout(out):
                    exec(compile(code, path.name, "exec"), namespace)
                last = out.getvalue()
            outputs.append(last)
    finally:
        os.chdir(previous)
    return namespace


def _run_commands(path, code, folder, mark, video):
    printed = []
    for command in (line for line in code.replace("\\\n", " ").splitlines() if line.strip()):
        if not video:
            command = re.sub(r"\s--out\s+\S+\.(mp4|gif)", "", command)
        done = _shell(command, folder)
        want = int(mark.split(":")[1]) if mark.startswith("exit:") else 0
        assert done.returncode == want, f"{path.name}: {command}\n{done.stdout}\n{done.stderr}"
        printed.append(done.stdout + done.stderr)
    return "\n".join(printed)


def test_there_are_three_tutorials_and_each_is_in_the_site():
    import yaml

    nav = str(yaml.safe_load((ROOT / "mkdocs.yml").read_text())["nav"])
    assert len(TUTORIALS) == 3 and all(t.name in nav for t in TUTORIALS)


def test_the_pddl_tutorial_runs_as_written(tmp_path):
    run_tutorial(ROOT / "docs" / "tutorial_pddl.md", tmp_path, video=False)
    assert (tmp_path / "gems.plan").exists() and not list(tmp_path.glob("*.mp4"))


@pytest.mark.slow
def test_the_pddl_tutorial_renders_its_video(tmp_path):
    run_tutorial(ROOT / "docs" / "tutorial_pddl.md", tmp_path)
    video = tmp_path / "gems.mp4"
    assert video.stat().st_size > 10_000 and (tmp_path / "gems.mp4.json").exists()


def test_the_python_api_tutorial_runs_as_written(tmp_path):
    namespace = run_tutorial(ROOT / "docs" / "tutorial_api.md", tmp_path)
    assert namespace["plan"].solved and namespace["run"].reached


def test_the_gymnasium_tutorial_runs_as_written_up_to_stable_baselines3(tmp_path):
    namespace = run_tutorial(ROOT / "docs" / "tutorial_gymnasium.md", tmp_path)
    assert namespace["env"].observation_space.contains(namespace["obs"])
