"""Re-run the outputs that must stay byte-identical (issue 30) and compare them with a reference.

Usage::

    python scripts/byte_identity.py --reference DIR            # compare with files made by older code
    python scripts/byte_identity.py --digests tests/data/byte_identity.json [--cheap]
    python scripts/byte_identity.py --write-digests FILE [--cheap] [--keep DIR]

The commands (run in a temporary folder, ``C`` = ``python -m csql_sim``, ``L`` = the
lifted rules shipped before issue 33 retrained them, :data:`LIFTED`) are
:data:`COMMANDS`. Only the provenance values ``version`` and ``python`` may differ:
:func:`normalized` blanks them (string values of those keys in JSON and indented YAML
lines; format versions are integers and stay). One field was
added on purpose and is left out of the comparison: a physical report's ``"legend"``
(object name -> cube colour, issue 30 item 4). An ``.npz`` rule
base is compared array by array, its header normalized the same way. One line per file;
exit 1 on any difference or missing file.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LIFTED = ROOT / "tests" / "data" / "byte_identity_lifted.json"
"""The lifted rules the reference outputs were made with: the file shipped before issue 33 retrained it."""
_JSON_PROVENANCE = re.compile(r'"(version|python)": "[^"]*"')
_YAML_PROVENANCE = re.compile(r"^(\s+)(version|python): (?![0-9]+\s*$)\S.*$", re.MULTILINE)
_JSON_LEGEND = re.compile(r'\n\s*"legend": \{[^{}]*\},')


def commands(lifted: str = "lifted.json") -> list[tuple[list[str], str | None, bool]]:
    """(arguments, file that receives stdout or None, cheap) for every output compared."""
    out: list[tuple[list[str], str | None, bool]] = [
        (["train", "--blocks", "3", "--seed", "0", "--out", "train3.yaml"], None, True),
        (["train", "--blocks", "4", "--seed", "0", "--out", "train4.yaml"], None, True),
        (["train", "--blocks", "5", "--seed", "0", "--out", "train5.npz"], None, False),
        (["evaluate", "--blocks", "3", "--pairs", "6", "--seed", "1", "--json", "ev3.json", "--quiet"], None, True),
    ]
    for n in (7, 10, 20, 26):
        for tag, planner in (("l", ["--rules", lifted]), ("g", ["--planner", "gn1"])):
            base = ["plan", "--blocks", str(n), "--pairs", "20", "--seed", "5", *planner]
            out.append((base, f"plan_{tag}_{n}.txt", True))
            out.append(([*base, "--json", f"plan_{tag}_{n}.json"], None, True))
    seven = ["plan", "--start", "GFEDCBA", "--goal", "ABCDEFG", "--rules", lifted]
    z26 = ["plan", "--start", "ZYXWVUTSRQPONMLKJIHGFEDCBA", "--goal", "ABCDEFGHIJKLMNOPQRSTUVWXYZ", "--planner", "gn1"]
    out += [(seven, "single7.txt", True), ([*seven, "--json", "single7.json"], None, True),
            ([*z26, "--json", "single26.json", "--plan-out", "single26.plan"], None, True), (z26, "single26.txt", True),
            (["plan", "--start", "CBA", "--goal", "BAC"], "g3.txt", True),
            (["plan", "--start", "CBA", "--goal", "BAC", "--json", "g3.json"], None, True),
            (["plan", "--blocks", "4", "--pairs", "30", "--seed", "2", "--json", "g4p.json"], None, True),
            (["plan", "--start", "CBA", "--goal", "BAC", "--rules", "train3.yaml", "--json", "g3r.json"], None, True)]
    return out


def outputs(cheap: bool) -> list[str]:
    """The files the commands make (those of the cheap ones only with ``cheap``)."""
    names = []
    for args, stdout, is_cheap in commands():
        if cheap and not is_cheap:
            continue
        if stdout:
            names.append(stdout)
        names += [args[i + 1] for i, a in enumerate(args) if a in ("--out", "--json", "--plan-out")]
    return names


def run_all(folder: Path, cheap: bool, lifted: str | None = None) -> None:
    """Run the commands in ``folder`` with this checkout's package.

    ``lifted``: the path the commands name the lifted rules by (it is recorded in the
    reports); None copies them into ``folder`` as ``lifted.json``, so that the outputs do
    not depend on where the checkout is.
    """
    if lifted is None:
        shutil.copyfile(LIFTED, folder / "lifted.json")
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    for args, stdout, is_cheap in commands(lifted or "lifted.json"):
        if cheap and not is_cheap:
            continue
        done = subprocess.run([sys.executable, "-m", "csql_sim", *args], cwd=folder, env=env, capture_output=True,
                              text=True, check=False)
        if done.returncode not in (0, 1):
            raise SystemExit(f"{' '.join(args)}: exit {done.returncode}: {done.stderr.strip()[-500:]}")
        if stdout:
            (folder / stdout).write_text(done.stdout)


def normalized(text: str) -> str:
    """``text`` with the provenance values ``version`` and ``python`` blanked (JSON and YAML), the legend left out."""
    text = _JSON_LEGEND.sub("", text)
    return _YAML_PROVENANCE.sub(r"\1\2: _", _JSON_PROVENANCE.sub(r'"\1": "_"', text))


def digest(path: Path) -> str:
    """sha256 of the normalized content (for an .npz: of every array's bytes, the header normalized)."""
    h = hashlib.sha256()
    if path.suffix == ".npz":
        import numpy as np

        with np.load(path) as z:
            for key in sorted(z.files):
                value = z[key]
                h.update(key.encode() + str(value.dtype).encode() + str(value.shape).encode())
                h.update(normalized(str(value)).encode() if key == "header" else value.tobytes())
    else:
        h.update(normalized(path.read_text()).encode())
    return h.hexdigest()


def compare(folder: Path, want: dict[str, str]) -> int:
    """Print one line per file; the number of files that differ or are missing."""
    bad = 0
    for name, expected in want.items():
        path = folder / name
        got = digest(path) if path.exists() else None
        ok = got == expected
        bad += not ok
        print(f"{'same' if ok else 'DIFFERENT' if got else 'MISSING'}  {name}  {got or '-'}")
    return bad


def main(argv: list[str] | None = None) -> int:
    """See the module docstring."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    what = ap.add_mutually_exclusive_group(required=True)
    what.add_argument("--reference", type=Path, help="a folder of outputs made by the reference code")
    what.add_argument("--digests", type=Path, help="a JSON file of {file: sha256 of the normalized content}")
    what.add_argument("--write-digests", type=Path, help="write the digests of this code's outputs to this file")
    ap.add_argument("--cheap", action="store_true", help="only the cheap outputs (no 5-block npz)")
    ap.add_argument("--lifted", help="name the lifted rules by this path (as the reference's commands did, e.g. "
                                      "/work/main/assets/rules/lifted.json); default: a copy named lifted.json")
    ap.add_argument("--keep", type=Path, help="make the outputs in this (empty) folder instead of a temporary one")
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        folder = args.keep or Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        run_all(folder, args.cheap, args.lifted)
        names = outputs(args.cheap)
        if args.write_digests:
            doc = {name: digest(folder / name) for name in names}
            args.write_digests.write_text(json.dumps(doc, indent=1, sort_keys=True) + "\n")
            print(f"wrote {len(doc)} digests to {args.write_digests}")
            return 0
        if args.digests:
            stored = json.loads(args.digests.read_text())
            want = {name: stored[name] for name in names if name in stored}
        else:
            want = {name: digest(args.reference / name) for name in names if (args.reference / name).exists()}
        missing = [name for name in names if name not in want]
        for name in missing:
            print(f"MISSING  {name}  (not in the reference)")
        return 1 if compare(folder, want) + len(missing) else 0


if __name__ == "__main__":
    sys.exit(main())
