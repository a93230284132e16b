"""Errors for bad user input: each renders as one line naming the file and the problem."""
from __future__ import annotations

import difflib
import os
from collections.abc import Iterable


class InputError(Exception):
    """Bad user input (file, value or option); the CLI prints it on one line and exits 2.

    Args:
        problem: what is wrong, in words a user understands.
        path: the offending file, if any (named first in the message).
        line: 1-based line number inside ``path``, if known.
    """

    exit_code = 2

    def __init__(self, problem: str, path: os.PathLike | str | None = None,
                 line: int | None = None):
        self.problem = problem
        self.path = None if path is None else os.fspath(path)
        self.line = line
        super().__init__(self.one_line())

    def one_line(self) -> str:
        """The message as a single line: ``path:line: problem``."""
        where = ""
        if self.path is not None:
            where = self.path if self.line is None else f"{self.path}:{self.line}"
            where += ": "
        return (where + self.problem).replace("\n", " ")


def did_you_mean(word: str, choices: Iterable[str]) -> str:
    """A ' (did you mean X?)' hint for a misspelt ``word``, or '' when nothing is close."""
    close = difflib.get_close_matches(word, list(choices), n=1, cutoff=0.6)
    return f" (did you mean '{close[0]}'?)" if close else ""


def require_file(path: os.PathLike | str, what: str = "file") -> str:
    """Return ``path`` as str, or raise InputError when it is not an existing file."""
    path = os.fspath(path)
    if not os.path.exists(path):
        raise InputError(f"{what} not found", path)
    if not os.path.isfile(path):
        raise InputError(f"{what} is not a regular file", path)
    return path
