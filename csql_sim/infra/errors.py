"""The one exception family the CLI turns into a one-line error and exit status 2."""

import re


class CsqlError(ValueError):
    """Bad input from a user: a malformed message, an unknown block, a corrupt file."""


class Terminated(KeyboardInterrupt):
    """SIGTERM arrived: unwinds as Ctrl-C does (``finally`` blocks run, workers and Ray stop).

    A KeyboardInterrupt, so every clean-up path written for Ctrl-C also runs for it; the
    command line reports it as ``terminated`` (exit status 143) rather than ``interrupted``.
    """


QUOTED_CHARS = 60
"""The most characters of a token a message quotes (then ``...``)."""


def shortened(text: str, total: int = 200) -> str:
    """``text`` for a one-line message: each quoted token cut to :data:`QUOTED_CHARS`, the whole to ``total``."""
    text = re.sub(r"""(['"])([^'"]{""" + str(QUOTED_CHARS + 1) + r""",})\1""",
                  lambda m: m.group(1) + m.group(2)[:QUOTED_CHARS] + "..." + m.group(1), text)
    return text if len(text) <= total else text[:total] + "..."
