"""The contact-model protocol and its one registry.

A rough-surface contact model is a :class:`ContactModel`: its name, its cost rank (``model="auto"``
tries the models cheapest first), its typed options (the keyword arguments it takes, with their
defaults and checks), its default distance grid and its kernel, plus a few optional hooks. Every
model is one value of one registry (as ``xarray`` backends are entry points of one table and
``flox`` aggregations values of one dict); :func:`roughstick.contact.curves` runs any of them
through the one pipeline of :mod:`roughstick.contact._pipeline`, and the rest of the package reads
the registry: ``model="auto"``, the trust layer's cost order, the ``.rough`` accessor, the
command line's ``--model`` choices and the API reference.

Adding a model is one sub-package and one call of :func:`register_model` (docs/architecture.md).
"""

from __future__ import annotations

import dataclasses
import inspect
import types
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from .._core.arguments import check_number
from .._core.conventions import CURVE_VARIABLES

__all__ = ["ContactModel", "Option", "Grid", "MODELS", "MODEL_CHOICES", "register_model",
           "unregister_model", "get_model", "model_names"]

#: Keyword arguments every model takes (the pipeline's own): not model options.
COMMON_PARAMETERS = ("height", "moments", "relative_humidity", "distance", "material", "material2",
                     "adsorbed_layer", "n_distance")


@dataclasses.dataclass(frozen=True)
class Option:
    """One keyword argument of a contact model: its default and how a value is checked.

    ``rule`` is a rule of :func:`roughstick._core.arguments.check_number` (``"positive"``,
    ``"count"``, a tuple of allowed numbers ...); ``check`` a callable that raises on a bad value
    and returns the value to use (choices of strings, pairs of numbers ...).
    """

    default: Any = None
    rule: str | tuple | None = None
    check: Callable[[Any], Any] | None = None

    def validate(self, name: str, value):
        if self.rule is not None:
            check_number(value, name, self.rule, example=self.default)
        return self.check(value) if self.check is not None else value


@dataclasses.dataclass(frozen=True)
class Grid:
    """A distance grid [m] (the output coordinate, ascending) and what was computed with it.

    ``per_rh``: the grids each humidity is solved on, when they differ (reported on
    ``distance``); ``curves``: the variables, ``(n_rh, n_distance)`` arrays, when the default
    grid computed them on the way (one eager map); ``automatic``: the default grid or a given one.
    """

    distance: np.ndarray
    per_rh: list | None = None
    curves: Mapping[str, np.ndarray] | None = None
    automatic: bool = True


@dataclasses.dataclass(frozen=True, eq=False)
class ContactModel:
    """A rough-surface contact model: what the pipeline needs to run it (the protocol).

    Required: ``name`` (the ``model=`` value), ``title`` (of the Dataset) and ``kernel``:
    ``kernel(z, distance, context) -> {variable: array (n_rh, n_distance)}`` for one eager map
    ``z`` [m] ``(ny, nx)``, the ascending distances [m] (or ``Grid.per_rh``) and the
    :class:`~roughstick.contact._pipeline.Context` (spacing, humidities as ``water_height`` and
    ``laplace_pressure`` arrays, moduli, ``options``). It returns ``variables`` (default: the
    variables of :data:`roughstick.conventions.CURVE_VARIABLES` but ``fit_error``, then
    ``extra_variables``); the curve variables it does not return are NaN.

    Optional: ``options`` (name -> :class:`Option`; keyword arguments outside them are refused);
    ``cost_rank`` (``model="auto"`` tries the models by increasing rank; ``None``: never chosen);
    ``default_grid(z, context) -> Grid`` (without it ``distance=`` is required); ``reference``
    (the boundary-element reference: its error is 0 by definition); ``complete_map`` (NaN pixels
    are refused, so ``"auto"`` skips it on maps with NaN); ``checks`` (the trust checks that apply:
    ``"validity"`` warns where the measured error bound exceeds the accuracy, ``"pixel"`` where
    the pixel does not resolve the water necks); ``memory`` (row of the memory table, or a
    function of the options giving it); ``estimate_seconds(shape, curves, points)``; and the hooks
    ``prepare(context)`` (model-specific input checks and settings), ``progress(context, grid)``
    (a :class:`roughstick._core.progress.WorkProgress` around the kernel's run, stepped by
    ``context.step()``), ``describe(context, grid) ->
    (attrs, history line)``, ``variable_attrs(context) -> {variable: attrs}`` (beyond
    ``conventions.ATTRS``), ``finish(dataset, context)`` (the model's own diagnostics), and
    ``run(context, grid) -> {variable: DataArray}`` for a model that does not map its kernel over
    the maps (Greenwood-Williamson maps it over spectral moments, given as a Dataset too:
    ``accepts_moments``; broadcasts the humidity: ``broadcast_humidity``; its default grid serves
    any moments: ``grid_needs_one_map=False``). ``function`` is the model's
    public function (the accessor's ``<name>_curves``), when it has one.

    Examples
    --------
    >>> import numpy as np
    >>> def kernel(z, distance, context):  # a flat punch of the map's highest point
    ...     gap = distance[None, :] - np.nanmax(z)
    ...     p = np.where(gap < context.water_height[:, None], context.laplace_pressure[:, None], 0.0)
    ...     return {"pressure": p, "wet_fraction": (p != 0).astype(float)}
    >>> toy = rs.contact.ContactModel(name="toy", title="toy contact", kernel=kernel,
    ...                               variables=("pressure", "wet_fraction"))
    >>> toy.bind({}), toy.solved_variables
    ({}, ('pressure', 'wet_fraction'))
    """

    name: str
    title: str
    kernel: Callable
    description: str = ""
    options: Mapping[str, Option] = dataclasses.field(default_factory=dict)
    cost_rank: float | None = None
    default_grid: Callable | None = None
    variables: tuple[str, ...] | None = None
    extra_variables: tuple[str, ...] = ()
    references: str = ""
    reference: bool = False
    complete_map: bool = False
    checks: tuple[str, ...] = ("pixel",)
    input_dims: tuple[str, ...] = ("y", "x")
    broadcast_humidity: bool = False
    accepts_moments: bool = False
    grid_needs_one_map: bool = True
    min_distances: int = 1
    memory: str | Callable | None = None
    estimate_seconds: Callable | None = None
    prepare: Callable | None = None
    progress: Callable | None = None
    describe: Callable | None = None
    finish: Callable | None = None
    variable_attrs: Callable | None = None
    run: Callable | None = None
    function: Callable | None = None

    def __post_init__(self):
        check_number(self.min_distances, "min_distances", "count", example=1)
        check_number(self.cost_rank, "cost_rank", "finite?")
        for field in ("name", "title"):
            if not isinstance(getattr(self, field), str):
                raise TypeError(f"ContactModel {field} must be a string, got {getattr(self, field)!r}.")
        if not callable(self.kernel):
            raise TypeError(f"ContactModel kernel must be a function, got {self.kernel!r}.")

    def bind(self, given: Mapping[str, Any]) -> dict:
        """The options of one call: ``given`` checked, completed with the defaults."""
        unknown = sorted(set(given) - set(self.options))
        if unknown:
            raise TypeError(f"unexpected keyword argument(s) {unknown} for model={self.name!r}.")
        return {name: opt.validate(name, given.get(name, opt.default))
                for name, opt in self.options.items()}

    @property
    def solved_variables(self) -> tuple[str, ...]:
        """What the kernel returns, in order: ``variables``, or the curve variables but
        ``fit_error`` and the extra variables."""
        if self.variables is not None:
            return tuple(self.variables)
        return (*(v for v in CURVE_VARIABLES if v != "fit_error"), *self.extra_variables)

    def memory_row(self, options: Mapping[str, Any]) -> str | None:
        """The row of ``roughstick._core.memory.CONTACT_BYTES_PER_PIXEL`` for these options."""
        return self.memory(options) if callable(self.memory) else self.memory


def options_of(function: Callable, **rules) -> dict[str, Option]:
    """The options of a model from its public function's keyword-only arguments (their defaults:
    one source) and ``rules``: name -> a rule of ``check_number`` or an :class:`Option` check."""
    out = {}
    for p in inspect.signature(function).parameters.values():
        if p.kind is not p.KEYWORD_ONLY or p.name in COMMON_PARAMETERS:
            continue
        rule = rules.get(p.name)
        out[p.name] = Option(p.default, rule=None if callable(rule) else rule,
                             check=rule if callable(rule) else None)
    return out


_REGISTRY: dict[str, ContactModel] = {}

#: The contact models by name, cheapest first (a read-only, live view of the one registry).
MODELS: Mapping[str, ContactModel] = types.MappingProxyType(_REGISTRY)


def register_model(model: ContactModel, *, replace: bool = False) -> ContactModel:
    """Add a contact model to the registry (``model=model.name`` everywhere); returns it.

    Examples
    --------
    >>> import numpy as np
    >>> def kernel(z, distance, context):
    ...     return {"pressure": np.zeros((context.water_height.size, distance.size))}
    >>> toy = rs.contact.register_model(rs.contact.ContactModel(name="toy", title="toy", kernel=kernel))
    >>> "toy" in rs.contact.MODELS, "toy" in rs.contact.model_names(auto=True)
    (True, True)
    >>> rs.contact.unregister_model("toy")
    """
    if not isinstance(model, ContactModel):
        raise TypeError(f"register_model takes a roughstick.contact.ContactModel, got {type(model).__name__}.")
    if not model.name.isidentifier() or model.name == "auto":
        raise ValueError(f"a model name must be a Python identifier other than 'auto', got {model.name!r}.")
    if model.name in _REGISTRY and not replace and _REGISTRY[model.name] is not model:
        raise ValueError(f"a contact model named {model.name!r} is registered already; pass replace=True.")
    unknown = sorted(set(model.checks) - {"validity", "pixel"})
    if unknown:
        raise ValueError(f"unknown trust checks {unknown}: give 'validity' and/or 'pixel'.")
    _REGISTRY[model.name] = model
    ranked = [_REGISTRY[n] for n in model_names()]  # the view iterates cheapest first
    _REGISTRY.clear()
    _REGISTRY.update((m.name, m) for m in ranked)
    return model


def unregister_model(name: str) -> None:
    """Remove a contact model from the registry."""
    if name not in _REGISTRY:
        raise KeyError(f"no contact model named {name!r}; the registered ones are {model_names()}.")
    del _REGISTRY[name]


def model_names(*, auto: bool = False) -> tuple[str, ...]:
    """Names of the registered models, cheapest first (those without a cost rank last);
    ``auto=True`` appends ``"auto"`` (the values ``model=`` takes)."""
    ranked = sorted(_REGISTRY.values(), key=lambda m: (m.cost_rank is None, m.cost_rank or 0.0))
    return tuple(m.name for m in ranked) + (("auto",) if auto else ())


def get_model(name: str) -> ContactModel:
    """The registered model of this name (``ValueError`` naming the choices otherwise)."""
    try:
        return _REGISTRY[name]
    except (KeyError, TypeError):
        raise ValueError(f"model must be one of {model_names(auto=True)}, got {name!r}.") from None


class ModelChoices:
    """The values ``model=`` takes, read from the registry when asked (for ``argparse`` choices
    and configuration keys built before a model is registered)."""

    def __init__(self, *, auto: bool = True):
        self.auto = auto

    def __iter__(self):
        return iter(model_names(auto=self.auto))

    def __contains__(self, name) -> bool:
        return name in model_names(auto=self.auto)

    def __len__(self) -> int:
        return len(model_names(auto=self.auto))

    def __repr__(self) -> str:
        return repr(model_names(auto=self.auto))


#: The values ``model=`` takes (the registered names and "auto"), read from the registry each time.
MODEL_CHOICES = ModelChoices()
