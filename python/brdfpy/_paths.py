"""File paths as the public functions take them: ``str``, ``bytes`` or :class:`os.PathLike`, nothing else.

``open(3)`` opens file descriptor 3 and ``open(0)`` reads standard input, so an integer where a path is
meant must be refused before it reaches ``open`` (or Pillow, or the compiled module).
"""

from __future__ import annotations

import os


def as_path(name: str, path: object) -> str:
    """``path`` as a ``str`` path; a ``TypeError`` naming ``name`` for anything that is not a path, a
    ``ValueError`` naming it for an empty path or one with a NUL character (which no file has: ``open``
    would say "embedded null byte" or quote an empty name, naming nothing)."""
    if isinstance(path, (str, bytes)) or hasattr(type(path), "__fspath__"):
        p = os.fsdecode(os.fspath(path))  # type: ignore[call-overload]
        if not p:
            raise ValueError(f"{name}: is empty (expected a file path)")
        if "\0" in p:
            raise ValueError(f"{name}: contains a NUL character, which no file path can hold: {p!r}")
        return p
    raise TypeError(f"{name}: expected a file path (str or os.PathLike), got {type(path).__name__}")
