"""The one exception family the CLI turns into a one-line error and exit status 2."""


class CsqlError(ValueError):
    """Bad input from a user: a malformed message, an unknown block, a corrupt file."""


class Terminated(KeyboardInterrupt):
    """SIGTERM arrived: unwinds as Ctrl-C does (``finally`` blocks run, workers and Ray stop).

    A KeyboardInterrupt, so every clean-up path written for Ctrl-C also runs for it; the
    command line reports it as ``terminated`` (exit status 143) rather than ``interrupted``.
    """
