"""The one exception family the CLI turns into a one-line error and exit status 2."""


class CsqlError(ValueError):
    """Bad input from a user: a malformed message, an unknown block, a corrupt file."""
