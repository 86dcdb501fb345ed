"""The rule asset ships inside the wheel and is found through importlib.resources."""

import subprocess
import sys
import zipfile
from pathlib import Path

from csql_sim.core.classifiers.r_classifier import load_paper_rules


def test_the_asset_is_found_in_this_install():
    assert len(load_paper_rules()) == 36


def test_the_asset_is_found_from_a_built_wheel(tmp_path):
    root = Path(__file__).resolve().parents[1]
    build = subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(tmp_path), str(root)],
        capture_output=True, text=True, timeout=300,
    )
    assert build.returncode == 0, build.stderr
    wheel = next(tmp_path.glob("csql_sim-*.whl"))
    names = zipfile.ZipFile(wheel).namelist()
    assert "csql_sim/assets/rules/blocks3.yaml" in names
    site = tmp_path / "site"
    zipfile.ZipFile(wheel).extractall(site)
    code = "import csql_sim.core.classifiers.r_classifier as r; print(r.__file__); print(len(r.load_paper_rules()))"
    # -S: no site processing, so this checkout's editable install is invisible; the
    # dependencies still come from the running environment's site-packages, after the wheel.
    deps = next(p for p in sys.path if p.endswith("site-packages"))
    run = subprocess.run([sys.executable, "-S", "-c", code], capture_output=True, text=True, timeout=60,
                         env={"PYTHONPATH": f"{site}:{deps}", "PATH": "/usr/bin:/bin"}, cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    where, count = run.stdout.split()
    assert where.startswith(str(site)) and count == "36"


def test_the_asset_is_found_from_a_source_checkout_without_an_install(tmp_path):
    root = Path(__file__).resolve().parents[1]
    code = "import csql_sim.core.classifiers.r_classifier as r; print(r.__file__); print(len(r.load_paper_rules()))"
    deps = next(p for p in sys.path if p.endswith("site-packages"))
    run = subprocess.run([sys.executable, "-S", "-c", code], capture_output=True, text=True, timeout=60,
                         env={"PYTHONPATH": f"{root}:{deps}", "PATH": "/usr/bin:/bin"}, cwd=tmp_path)
    assert run.returncode == 0, run.stderr
    where, count = run.stdout.split()
    assert where.startswith(str(root)) and count == "36"
