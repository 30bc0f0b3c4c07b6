"""Refuse the old spellings of renamed arguments with a ``TypeError`` that names the new one.

brdfpy uses one name per concept (``n`` is always the surface normal, a choice of term is a keyword named as
the model parameter that picks it); calls written against an older signature fail with a message that says
what to write instead, rather than with Python's generic "unexpected keyword argument".
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from typing import Any, TypeVar, cast

__all__ = ["name_is_keyword", "renamed_keywords"]

# The decorated function keeps its signature for type checkers and for inspect (functools.wraps).
F = TypeVar("F", bound=Callable[..., Any])


def renamed_keywords(**renames: str) -> Callable[[F], F]:
    """Refuse ``old=`` keywords (``renamed_keywords(n="samples")``), naming the new keyword."""

    def wrap(f: F) -> F:
        @functools.wraps(f)
        def call(*args: Any, **kwargs: Any) -> Any:
            for old, new in renames.items():
                if old in kwargs:
                    raise TypeError(f"{f.__name__}(): {old}= is now {new}= (got {old}={kwargs[old]!r})")
            return f(*args, **kwargs)

        return cast(F, call)

    return wrap


def name_is_keyword(keyword: str, example: str) -> Callable[[F], F]:
    """Refuse a string as the first positional argument (the old place of a term's name), naming the keyword
    that takes it now; ``example`` shows the new call."""

    def wrap(f: F) -> F:
        @functools.wraps(f)
        def call(*args: Any, **kwargs: Any) -> Any:
            if args and isinstance(args[0], str):
                raise TypeError(
                    f"{f.__name__}(): the name {args[0]!r} goes in the keyword {keyword}= now, e.g. {example}"
                )
            return f(*args, **kwargs)

        return cast(F, call)

    return wrap
