"""Parameter files and overrides: a learner's defaults for n blocks with a dict or a YAML file on top.

Split from :mod:`csql_sim.learners.params`, which re-exports every function here.
"""

from __future__ import annotations

import dataclasses
import os
from dataclasses import fields

from csql_sim.infra.files import InputFileError, load_yaml, read_text_file
from csql_sim.learners.params import (
    MAX_FILE_BYTES,
    PARAMS_BY_METHOD,
    CommonParams,
    ParamsError,
    _shown,
    default_params,
    defaults_for_blocks,
)


def with_overrides(params: CommonParams, overrides: dict, source: str = "parameters") -> CommonParams:
    """Replace fields of ``params``; an unknown key or a wrong type is a ParamsError."""
    known = {f.name: f for f in fields(params)}
    clean = {}
    for key, value in overrides.items():
        if key not in known:
            raise ParamsError(f"{source}: unknown parameter {key!r} for {type(params).__name__}")
        current = getattr(params, key)
        if isinstance(current, bool):
            ok = isinstance(value, bool)
        elif isinstance(current, int):
            ok = isinstance(value, int) and not isinstance(value, bool)
        else:
            ok = isinstance(value, (int, float)) and not isinstance(value, bool)
            try:
                value = float(value) if ok else value
            except OverflowError:
                raise ParamsError(f"{source}: {key} must be a finite float64, got {_shown(value)}") from None
        if not ok:
            raise ParamsError(f"{source}: {key} must be {type(current).__name__}, got {value!r}")
        clean[key] = value
    try:
        return dataclasses.replace(params, **clean)
    except ParamsError as exc:
        raise ParamsError(f"{source}: {exc}") from None


def load_params(path: str | os.PathLike, method: str, n: int = 3) -> CommonParams:
    """Defaults of ``method`` for n blocks overridden by a YAML mapping.

    The file is either a flat mapping of parameters, or a mapping from method names to
    such mappings (only ``method``'s entry is applied).
    """
    p = os.fspath(path)
    try:
        doc = load_yaml(read_text_file(p, MAX_FILE_BYTES, "parameter file"), p)
    except InputFileError as exc:
        raise ParamsError(str(exc)) from None
    except (ValueError, OverflowError) as exc:  # a value PyYAML cannot build: an integer of 5,000 digits
        raise ParamsError(f"{p}: a YAML value cannot be read ({exc.__class__.__name__})") from None
    if doc is None:
        doc = {}
    if not isinstance(doc, dict):
        raise ParamsError(f"{p}: expected a mapping of parameter names to values")
    if any(k in PARAMS_BY_METHOD for k in doc):
        stray = [k for k in doc if k not in PARAMS_BY_METHOD]
        if stray:
            raise ParamsError(f"{p}: unknown method {stray[0]!r}")
        doc = doc.get(method) or {}
        if not isinstance(doc, dict):
            raise ParamsError(f"{p}: the entry for {method} must be a mapping")
    return with_overrides(defaults_for_blocks(method, n), doc, source=str(p))


def resolve_params(
    method: str, params: CommonParams | dict | str | os.PathLike | None, n: int = 3
) -> CommonParams:
    """Parameters from None (the defaults for n blocks), a dataclass, a dict of overrides or a YAML path."""
    if params is None:
        return defaults_for_blocks(method, n)
    if isinstance(params, CommonParams):
        expected = PARAMS_BY_METHOD.get(method)
        if expected is None:
            default_params(method)
        if type(params) is not expected:
            raise ParamsError(f"{method} needs {expected.__name__}, got {type(params).__name__}")
        return params
    if isinstance(params, dict):
        return with_overrides(defaults_for_blocks(method, n), params)
    return load_params(params, method, n)
