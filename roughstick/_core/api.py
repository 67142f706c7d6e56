"""How the public API evolves: old keyword names keep working for a while, and say the new one.

:func:`renamed_keywords` maps a renamed keyword argument to its new name with a
``DeprecationWarning`` that names the new keyword; the old top-level names of the package are
served by ``roughstick.__getattr__`` from the table in :mod:`roughstick._renamed`.
"""

from __future__ import annotations

import functools
import inspect
import warnings

__all__ = ["renamed_keywords"]


def renamed_keywords(**old_to_new: str):
    """Decorator: accept each old keyword ``old`` as the new ``new``, with a DeprecationWarning.

    Both given at once is a ``TypeError`` naming both. The warning points at the caller's line.

    Examples
    --------
    >>> import warnings
    >>> from roughstick._core.api import renamed_keywords
    >>> @renamed_keywords(tolerance="accuracy")
    ... def f(*, accuracy=0.05):
    ...     return accuracy
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     f(tolerance=0.1), str(caught[0].message)
    (0.1, 'f(tolerance=...) is now f(accuracy=...); the old keyword will be removed')
    """

    def decorate(func):
        params = inspect.signature(func).parameters
        for new in old_to_new.values():
            if new not in params and not any(p.kind is p.VAR_KEYWORD for p in params.values()):
                raise TypeError(f"{func.__qualname__} has no keyword {new!r} to rename to")

        @functools.wraps(func)
        def wrapper(*args, **kwargs):
            for old, new in old_to_new.items():
                if old in kwargs:
                    if new in kwargs:
                        raise TypeError(f"{func.__name__}() got both {old}= (the old name) and "
                                        f"{new}=; pass {new}= only")
                    warnings.warn(f"{func.__name__}({old}=...) is now {func.__name__}({new}=...); "
                                  "the old keyword will be removed", DeprecationWarning, stacklevel=2)
                    kwargs[new] = kwargs.pop(old)
            return func(*args, **kwargs)

        wrapper.__renamed_keywords__ = dict(old_to_new)
        return wrapper

    return decorate
