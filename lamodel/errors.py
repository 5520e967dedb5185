"""Errors that lamodel reports to its users as one clear line."""


class InputError(ValueError):
    """Bad input: a file, a field or a value that cannot describe a block assembly.

    The message is a complete one-line sentence naming where the problem is, what is wrong
    and what was expected; the command-line tools print it and exit with status 2.
    """


class SolverError(RuntimeError):
    """A solver could not be run at all (missing library, malformed model)."""


class OutputError(OSError):
    """The results could not be written (a full disk, a folder made read-only during the
    run); the message names the folder. The command-line tools print it and exit with
    status 1."""
