"""File paths as the public functions take them: ``str``, ``bytes`` or :class:`os.PathLike`, nothing else.

``open(3)`` opens file descriptor 3 and ``open(0)`` reads standard input, so an integer where a path is
meant must be refused before it reaches ``open`` (or Pillow, or the compiled module).
"""

from __future__ import annotations

import os


def as_path(name: str, path: object) -> str:
    """``path`` as a ``str`` path; a ``TypeError`` naming ``name`` for anything that is not a path."""
    if isinstance(path, (str, bytes)) or hasattr(type(path), "__fspath__"):
        return os.fsdecode(os.fspath(path))  # type: ignore[call-overload]
    raise TypeError(f"{name}: expected a file path (str or os.PathLike), got {type(path).__name__}")
