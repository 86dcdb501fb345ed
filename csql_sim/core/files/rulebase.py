"""Rule files: read and write a :class:`RuleBase` in either form, chosen by suffix.

``*.npz`` files are the compact form (:mod:`csql_sim.core.files.rulebase_npz`), anything else
is versioned YAML (:mod:`csql_sim.core.files.rulebase_yaml`, which also defines the record), so
every reader reads both. Writes are atomic (temporary file, then rename).
"""

from __future__ import annotations

import os
from pathlib import Path

from csql_sim.core.classifiers.q_classifier import QClassifier
from csql_sim.core.files import rulebase_npz
from csql_sim.core.files.rulebase_yaml import (
    FORMAT,
    MAX_FILE_BYTES,
    VERSION,
    RuleBase,
    RuleBaseError,
    dumps,
    load_file,
    loads,
)
from csql_sim.infra import formats
from csql_sim.infra.files import write_atomic

__all__ = ["FORMAT", "MAX_FILE_BYTES", "VERSION", "RuleBase", "RuleBaseError", "dumps", "file_bytes", "is_npz",
           "load", "load_r_classifiers", "loads", "other_model", "save"]


def is_npz(path: str | os.PathLike) -> bool:
    """Whether ``path`` names the compact binary form (suffix ``.npz``, :mod:`csql_sim.core.files.rulebase_npz`)."""
    return Path(path).suffix.lower() == ".npz"


def other_model(path: str | os.PathLike, name: str | None) -> str | None:
    """Why ``path``, a model of format ``name``, is no single ground rule file; None if it is one or no model."""
    if name not in formats.MODEL_FORMATS - {formats.RULE_BASE, formats.RULE_BASE_NPZ}:
        return None
    what = "a sharded rule base" if name == formats.SHARDS else f"a {name} file"
    hint = "" if name == formats.LIFTED_RULES else f"; plan with it: csql-sim plan --rules {os.fspath(path)}"
    return f"{os.fspath(path)} is {what}, not a single ground rule file from 'csql-sim train'{hint}"


def file_bytes(path: str | os.PathLike, rulebase: RuleBase) -> str | bytes:
    """The content :func:`save` would write to ``path``: npz bytes or YAML text, by suffix."""
    if is_npz(path):
        return rulebase_npz.to_bytes(rulebase)
    return dumps(rulebase)


def save(path: str | os.PathLike, rulebase: RuleBase) -> Path:
    """Write ``rulebase`` to the file ``path`` atomically (temporary file, then rename); npz by suffix.

    Args:
        path: the rule file to write (``*.npz``: the compact binary form).
        rulebase: the classifier list and its provenance.

    Returns:
        The path written.

    Raises:
        TypeError: if the arguments are swapped or ``rulebase`` is not a RuleBase.
    """
    if not isinstance(rulebase, RuleBase):
        hint = " (the arguments are swapped: save(path, rulebase))" if isinstance(path, RuleBase) else ""
        raise TypeError(f"save() needs a RuleBase as 'rulebase', got {type(rulebase).__name__}{hint}")
    if is_npz(path):
        return rulebase_npz.save(path, rulebase)
    return write_atomic(path, dumps(rulebase))


def load(path: str | os.PathLike, blocks: int | None = None, progress: bool = False) -> RuleBase:
    """Read a rule base (``*.npz`` or YAML); any problem is a one-line RuleBaseError naming the file.

    Args:
        path: the rule file.
        blocks: the number of blocks the caller expects; a YAML file for another number is
            refused after reading its header, before the classifiers are parsed.
        progress: show a tqdm bar on stderr while the classifiers are parsed (when that
            takes more than a second).
    """
    problem = other_model(path, formats.sniff(path))
    if problem:
        raise RuleBaseError(problem)
    if is_npz(path):
        rulebase = rulebase_npz.load(path, RuleBaseError)
        if blocks is not None and rulebase.blocks != blocks:
            raise RuleBaseError(f"rule file {os.fspath(path)!r} is for {rulebase.blocks} blocks, not {blocks}")
        return rulebase
    return load_file(path, blocks, progress)


def load_r_classifiers(path: str | os.PathLike, n: int | None = None) -> RuleBase:
    """A rule file of R-classifiers only (a domain, e.g. from ``csql-sim discover``).

    Raises:
        RuleBaseError: if the file holds Q-classifiers, no rule at all, or is for another n.
    """
    rb = load(path)
    if n is not None and rb.blocks != n:
        raise RuleBaseError(f"{path} is for {rb.blocks} blocks, not {n}")
    if not rb.classifiers or any(isinstance(c, QClassifier) for c in rb.classifiers):
        raise RuleBaseError(f"{path} must hold R-classifiers only, and at least one")
    return rb
