"""Argument types shared by the subcommands (argparse turns their errors into one line)."""

from __future__ import annotations

import argparse
from collections.abc import Callable

from csql_sim.world import MAX_BLOCKS, MIN_BLOCKS


def int_type(minimum: int, maximum: int | None = None) -> Callable[[str], int]:
    """An argparse type accepting integers in ``[minimum, maximum]`` (no upper bound if None)."""
    if maximum is not None:
        what = f"an integer {minimum}..{maximum}"
    else:
        what = {0: "a non-negative integer", 1: "a positive integer"}.get(minimum, f"an integer >= {minimum}")

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be {what}, got {text!r}") from None
        if value < minimum or (maximum is not None and value > maximum):
            raise argparse.ArgumentTypeError(f"must be {what}, got {value}")
        return value

    return parse


positive_int = int_type(1)
non_negative_int = int_type(0)
blocks_arg = int_type(MIN_BLOCKS, MAX_BLOCKS)
