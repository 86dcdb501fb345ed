"""The kinds of rule file, told in one place from one read of the file: :func:`read_rule_file`.

A path given as ``--rules`` is one of :data:`KINDS`:

* a directory holding a manifest (``manifest.json``): a sharded rule base, :data:`SHARDED`;
* a file whose first bytes name the lifted format (``{"format": "csql-sim lifted
  q-classifiers"``): lifted Q-classifiers, :data:`LIFTED`;
* a zip file (first bytes ``PK``) or a name ending ``.npz``: an npz rule base, whose
  ``header`` array's ``meta.form`` tells the goal form (:data:`GOAL_NPZ`) from the index
  form (:data:`GROUND_NPZ`);
* any other file: a YAML rule base, whose header's ``meta.form`` tells :data:`GOAL_YAML`
  from :data:`GROUND_YAML`. A file that names another model format (lifted rules, a
  shard) is refused here, in one line.

The file is opened once and read once: its first bytes decide the format, and so the
size cap, then the rest is read. The loader of each kind
(:data:`csql_sim.core.policies.loader.LOADERS`) parses the bytes read here; whatever else
is wrong with the file, it names in one line.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

from csql_sim.core.files import rulebase_npz, rulebase_yaml
from csql_sim.core.files.rulebase import other_model
from csql_sim.core.files.rulebase_yaml import RuleBaseError
from csql_sim.core.state.goal_message import GOAL_FORM
from csql_sim.infra import formats
from csql_sim.infra.reading import InputFile, InputFileError

GROUND_YAML = "ground rule base (YAML)"
"""Index-form Q-classifiers in YAML: a greedy table."""
GOAL_YAML = "goal-form rule base (YAML)"
"""Goal-form Q-classifiers in YAML: a default hierarchy."""
GROUND_NPZ = "ground rule base (npz)"
"""Index-form Q-classifiers in npz: a greedy table."""
GOAL_NPZ = "goal-form rule base (npz)"
"""Goal-form Q-classifiers in npz: a default hierarchy."""
SHARDED = "sharded rule base"
"""A directory from goal-sharded training, read shard by shard."""
LIFTED = "lifted q-classifiers"
"""Lifted Q-classifiers (JSON), for any number of blocks."""
KINDS = (GROUND_YAML, GOAL_YAML, GROUND_NPZ, GOAL_NPZ, SHARDED, LIFTED)

MAX_LIFTED_Q_BYTES = 1 << 20
"""Largest lifted Q-classifier file read."""
WHAT = "rule file"
"""What a rule file is called in messages."""
NPZ, YAML = "npz", "yaml"
CAPS = {NPZ: (rulebase_npz.MAX_FILE_BYTES, WHAT), YAML: (rulebase_yaml.MAX_FILE_BYTES, WHAT),
        LIFTED: (MAX_LIFTED_Q_BYTES, "lifted Q-classifier file")}
"""The largest file read, and what it is called, for each codec of a rule file."""


@dataclass(frozen=True)
class RuleFile:
    """A rule file as read once: its kind, and its content for the kind's loader.

    Attributes:
        path: the path as given.
        kind: one of :data:`KINDS`.
        data: the bytes of an npz file (empty for the other kinds).
        decoded: the text of a YAML or lifted file (None for the other kinds).
        problem: why the file cannot be read as its kind (too large, not UTF-8), or None.
    """

    path: str | os.PathLike
    kind: str
    data: bytes = field(default=b"", repr=False)
    decoded: str | None = field(default=None, repr=False)
    problem: str | None = None

    @property
    def source(self) -> str:
        """The path as text, for messages."""
        return os.fspath(self.path)

    def content(self) -> bytes:
        """An npz file's bytes; the one-line RuleBaseError of ``problem`` if there is one."""
        if self.problem is not None:
            raise RuleBaseError(self.problem)
        return self.data

    def text(self) -> str:
        """A YAML or lifted file's text; the one-line RuleBaseError of ``problem`` if there is one."""
        if self.problem is not None or self.decoded is None:
            raise RuleBaseError(self.problem or f"{self.source}: not a text {WHAT}")
        return self.decoded


def read_rule_file(path: str | os.PathLike) -> RuleFile:
    """Open ``path`` once, read it once and tell its kind (module docstring).

    Raises:
        RuleBaseError: one line, if the path is missing, unreadable, not a regular file,
            too large for a rule file or another model's file.
    """
    if Path(path).is_dir() and (Path(path) / formats.SHARD_MANIFEST).is_file():
        return RuleFile(path, SHARDED)
    try:
        with InputFile(path, WHAT, formats.HEAD_BYTES) as source:
            return _classify(path, source)
    except InputFileError as exc:
        raise RuleBaseError(str(exc)) from None


def _classify(path: str | os.PathLike, source: InputFile) -> RuleFile:
    """The kind of an opened file from its first bytes, then (the cap known) its whole content, read once."""
    head = source.head
    npz = head.startswith(b"PK") or Path(path).suffix.lower() == ".npz"
    name = formats.SHARDS if head.startswith(formats.SHARD_MAGIC) else formats.head_format(head)
    lifted = not npz and name == formats.LIFTED_Q
    problem = None if npz or lifted else other_model(path, name)
    if problem:
        raise RuleBaseError(problem)
    cap, what = CAPS[NPZ if npz else LIFTED if lifted else YAML]
    try:
        data = source.read_all(cap, what)
    except InputFileError as exc:
        if not lifted:
            raise
        return RuleFile(path, LIFTED, problem=str(exc))  # told as lifted: its loader names the problem
    if npz:
        return RuleFile(path, GOAL_NPZ if rulebase_npz.header_meta(data).get("form") == GOAL_FORM else GROUND_NPZ, data)
    found = _text_file(path, LIFTED if lifted else GROUND_YAML, data)
    if lifted or found.decoded is None:
        return found
    if rulebase_yaml.header_meta(found.decoded, found.source).get("form") == GOAL_FORM:
        return RuleFile(path, GOAL_YAML, decoded=found.decoded)
    return found


def _text_file(path: str | os.PathLike, kind: str, data: bytes) -> RuleFile:
    """A text kind's file, decoded (a problem naming the first byte that is not UTF-8)."""
    try:
        return RuleFile(path, kind, decoded=data.decode("utf-8"))
    except UnicodeDecodeError as exc:
        return RuleFile(path, kind, problem=f"{os.fspath(path)}: not UTF-8 text (byte {exc.start})")
