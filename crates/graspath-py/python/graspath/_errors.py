"""The exceptions graspath raises, one class per kind of failure, all under :class:`GraspathError`.

The kind is the library's own classification of the error (``graspath::ErrorKind``), the same one
the ``graspath`` command's exit codes are derived from:

* a file that cannot be used as a file — an input missing or unreadable, an output path refused —
  is a :class:`GraspathFileError` (an :class:`OSError`); a missing input is a
  :class:`GraspathFileNotFoundError` (a :class:`FileNotFoundError`);
* bad content — a malformed file, a field or argument with a bad value, a size over a resource
  limit — is a :class:`GraspathValueError` (a :class:`ValueError`);
* anything else (writing output failed without an operating-system error, something unexpected) is
  a plain :class:`GraspathError`.

Every instance carries ``file`` and ``field``: the file and the field in it at fault (the most
specific ones the error names: a task's cloud file rather than the task file), or ``None``. The
message (``str(error)``) is the library's whole message, with the error's causes.
"""

from __future__ import annotations

from typing import Optional


class GraspathError(Exception):
    """An error reported by graspath: the base of every graspath exception."""

    #: The file (or input) at fault, as the message names it; ``None`` when none is named.
    file: Optional[str] = None
    #: The field, option or location in :attr:`file` at fault; ``None`` when none is named.
    field: Optional[str] = None


class GraspathFileError(GraspathError, OSError):
    """A file that cannot be used as a file: an input that is missing or cannot be read (a
    folder, a FIFO, no permission), an output path that is refused (it exists, it is a symbolic
    link or a device) or that cannot be written. ``errno`` is the operating system's error
    number when there is one."""


class GraspathFileNotFoundError(GraspathFileError, FileNotFoundError):
    """An input file that does not exist."""


class GraspathValueError(GraspathError, ValueError):
    """Bad content: a malformed file, a field or argument with a bad value or shape, an unknown
    name, or a size or count over a documented resource limit."""


__all__ = [
    "GraspathError",
    "GraspathFileError",
    "GraspathFileNotFoundError",
    "GraspathValueError",
]
