"""A warning's remedy spelled where the user is: a Python argument, a command-line flag or a
configuration key.

A warning that names a fix names a *setting* (the contact model, the pixel size, the check of the
pixel's cost) and asks :func:`spell` how to write it. The code the user called decides the
spelling for the duration of the call with :func:`spelled`: ``roughstick curves`` spells the
contact model ``--model fft_bem``, ``roughstick run`` ``model = "fft_bem"`` in its
[ensemble] table, :func:`roughstick.ensemble.run` ``model='fft_bem'``. The
outermost caller wins: a command's spelling is kept inside every function it calls, and the
function the user called from Python is kept inside the functions it calls in turn. Without any,
the setting's Python argument is named (``roughstick.contact.curves(..., model='fft_bem')``).

The spellings live in a :class:`contextvars.ContextVar`: they are seen by the code the caller
runs in its own thread, which is where the warnings that name a remedy are raised (once per
call, before the work is spread over threads).

Examples
--------
>>> from roughstick._core.remedy import argument, spell, spelled
>>> spell("contact_model", "auto", accuracy=0.1)
"roughstick.contact.curves(..., model='auto', accuracy=0.1)"
>>> with spelled(contact_model=lambda v, **kw: f"--model {v}"):
...     with spelled(contact_model=argument("model", call="roughstick.contact.curves")):
...         spell("contact_model", "fft_bem")
'--model fft_bem'
"""

from __future__ import annotations

import contextlib
import contextvars
from collections.abc import Callable

__all__ = ["spell", "spelled", "argument", "flag", "config_key", "SETTINGS"]

#: The settings a remedy may name, and what the value passed to :func:`spell` is.
SETTINGS = {
    "contact_model": "the contact model's name (keyword: accuracy, the accepted error of 'auto')",
    "spacing": "a pixel size [m] fine enough",
    "resolution": "how to measure what the pixel costs (no value)",
    "samples_per_level": "the samples per level of subset simulation",
    "height_distribution": "the height distribution of generated surfaces ('maps': the measured maps' own)",
    "surface_size": "a side length [m] of generated surfaces (the measured maps')",
    "levelling": "what is removed from a measured map as it is read ('plane', 'none', ...)",
}

_SPELLINGS: contextvars.ContextVar[dict | None] = contextvars.ContextVar("roughstick_remedy_spellings",
                                                                         default=None)


def argument(name: str, *, call: str | None = None, extra: tuple = ("accuracy",),
             fmt: Callable | None = None) -> Callable:
    """The spelling of a Python keyword argument: ``name=value`` (and the ``extra`` keywords
    given to :func:`spell`), inside ``call(..., )`` when ``call`` is given; ``fmt`` formats the
    value (default ``repr``)."""
    def say(value=None, **kw):
        args = [f"{name}={(fmt or repr)(value)}"] + [f"{k}={kw[k]!r}" for k in extra
                                                      if kw.get(k) is not None]
        return f"{call}(..., {', '.join(args)})" if call else ", ".join(args)
    return say


def flag(name: str, *, extra: dict | None = None, fmt: Callable | None = None) -> Callable:
    """The spelling of a command-line flag: ``--name value`` (and ``extra`` = {keyword: flag}
    for the further keywords given to :func:`spell`)."""
    def say(value=None, **kw):
        parts = [f"{name} {(fmt or str)(value)}"] + [f"{f} {kw[k]:g}" for k, f in (extra or {}).items()
                                                     if kw.get(k) is not None]
        return " ".join(parts)
    return say


def config_key(table: str, key: str, *, fmt: Callable | None = None) -> Callable:
    """The spelling of a configuration key: ``[table] key = "value"`` (``fmt`` formats the value
    as TOML, default a quoted string)."""
    def say(value=None, **kw):
        text = fmt(value) if fmt else '"' + str(value) + '"'
        return f"[{table}] {key} = {text}"
    return say


def _default(setting: str) -> Callable:
    if setting == "contact_model":
        return argument("model", call="roughstick.contact.curves")
    if setting == "spacing":
        return argument("spacing", fmt=lambda v: f"{v:.2g}")
    if setting == "samples_per_level":
        return argument("n_per_level", fmt=str)
    if setting == "height_distribution":
        return lambda value=None, **kw: (f"roughstick.ensemble.run(..., maps=maps, height_distribution={value!r})"
                                         if value == "maps" else f"height_distribution={value!r}")
    if setting == "levelling":
        return argument("levelling", call="roughstick.io.read_afm")
    if setting == "surface_size":
        return argument("size", fmt=lambda v: f"{v:.3g}")
    if setting == "resolution":
        return lambda value=None, **kw: ("roughstick.contact.resolution_study(height, relative_humidity=...) "
                                         "(the same map at half and twice the pixel)")
    raise KeyError(f"no remedy setting {setting!r}; known: {sorted(SETTINGS)}")


def spell(setting: str, value=None, **extra) -> str:
    """How the user sets ``setting`` to ``value`` where they are (see the module docstring)."""
    say = (_SPELLINGS.get() or {}).get(setting) or _default(setting)
    return say(value, **extra)


@contextlib.contextmanager
def spelled(**spellings: Callable):
    """Within the block, :func:`spell` writes these settings this way, unless an outer block
    (the code that called this one) already spells them: the outermost spelling wins."""
    for setting in spellings:
        if setting not in SETTINGS:
            raise KeyError(f"no remedy setting {setting!r}; known: {sorted(SETTINGS)}")
    token = _SPELLINGS.set({**spellings, **(_SPELLINGS.get() or {})})
    try:
        yield
    finally:
        _SPELLINGS.reset(token)
