"""One registry type for everything looked up by id.

Strategies, communication models, map-sharing mechanisms, map generators, sweep
engines and reproductions are each held in a :class:`Registry`: built-ins register
when their module is imported (``@REGISTRY.register`` or ``REGISTRY.register(obj)``),
or by reference when their module is slow to import and a run needs only one of them
(``REGISTRY.register_lazy(id, "module:attribute")``: the strategies, the sharing
mechanisms in modules of their own, the reproductions), imported on first lookup;
third-party packages through an entry-point group, loaded the first time an id is
missing or the registry is listed (as Gymnasium's ``register``/``make`` and
networkx's backends). Registries, with their entry-point groups and what an entry
point names:

* ``mrexplore.strategies.registry.STRATEGIES``: ``mrexplore.strategies``, a
  ``Strategy`` subclass;
* ``mrexplore.comm.COMM_MODELS``: ``mrexplore.comm``, a ``CommModel`` subclass;
* ``mrexplore.comm.SHARING``: ``mrexplore.sharing``, a ``MapSharing`` subclass;
* ``mrexplore.grid.GENERATORS``: ``mrexplore.generators``, a ``GeneratorInfo``;
* ``mrexplore.experiments.ENGINES``: ``mrexplore.engines``, an ``Engine`` subclass;
* ``mrexplore.experiments.reproduce.REPRODUCTIONS``: ``mrexplore.reproductions``, a
  ``Reproduction``.

An entry's id is its ``id`` attribute (``name`` for generators and engines); its
one-line summary is its ``summary`` attribute, else the first paragraph of its
docstring; its parameters are its ``params`` attribute, a mapping of names to
:class:`~mrexplore.params.Param`.

>>> from mrexplore.params import Param
>>> class Radio:
...     '''A made-up radio.'''
...     id = "radio"
...     params = {"power_dbm": Param(0.0, "dBm", "transmit power", low=-30, high=30)}
>>> RADIOS = Registry("radio")
>>> RADIOS.register(Radio) is Radio
True
>>> RADIOS.get("radio").__name__, RADIOS.summary("radio")
('Radio', 'A made-up radio.')
>>> RADIOS.resolve_params("radio", {"power_dbm": "10"})
{'power_dbm': 10.0}
>>> RADIOS.get("tv")
Traceback (most recent call last):
  ...
mrexplore.errors.UnknownIdError: unknown radio 'tv'; known: radio
"""

from __future__ import annotations

import importlib
import logging
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from importlib.metadata import entry_points
from typing import Any, Generic, TypeVar, overload

from mrexplore.errors import RegistryError, UnknownIdError
from mrexplore.params import Param, resolve_params

logger = logging.getLogger(__name__)

T = TypeVar("T")


def default_id(obj: object) -> str:
    """An object's id: its ``id`` attribute."""
    return str(getattr(obj, "id", "") or "")


def default_summary(obj: object) -> str:
    """An object's ``summary`` attribute, else the first paragraph of its docstring."""
    summary = getattr(obj, "summary", "")
    if isinstance(summary, str) and summary:
        return summary
    doc = (getattr(obj, "__doc__", None) or "").strip()
    return " ".join(line.strip() for line in doc.split("\n\n")[0].splitlines())


def default_params(obj: object) -> Mapping[str, Param]:
    """An object's ``params`` attribute, else no parameters."""
    params = getattr(obj, "params", None)
    return params if isinstance(params, Mapping) else {}


@dataclass(frozen=True)
class Entry(Generic[T]):
    """One registered id, for listings."""

    id: str
    obj: T
    summary: str
    params: Mapping[str, Param]
    plugin: str | None
    """The distribution that provided it through an entry point (``None``: built in)."""


class Registry(Generic[T]):
    """Ids to objects of one kind, with lazy entry-point plugins.

    ``kind`` names the kind in messages (``"strategy"``); ``group`` is the
    entry-point group plugins register under (``None``: no plugins). ``id_of``,
    ``summary_of`` and ``params_of`` read an object's id, one-line summary and
    parameter declarations (by default its ``id``, ``summary`` and ``params``).
    Ids iterate in registration order; :meth:`available` sorts them.
    """

    def __init__(
        self,
        kind: str,
        group: str | None = None,
        *,
        id_of: Callable[[T], str] = default_id,
        summary_of: Callable[[T], str] = default_summary,
        params_of: Callable[[T], Mapping[str, Param]] = default_params,
    ) -> None:
        self.kind = kind
        self.group = group
        self._id_of = id_of
        self._summary_of = summary_of
        self._params_of = params_of
        self._objects: dict[str, T] = {}
        self._lazy: dict[str, str] = {}
        self._order: dict[str, None] = {}  # every id, in registration order (lazy or not)
        self._lazy_summaries: dict[str, str] = {}
        self._plugin_of: dict[str, str] = {}
        self._plugins_loaded = False

    # ------------------------------------------------------------------ registering
    @overload
    def register(self, obj: T, *, id: str | None = None) -> T: ...

    @overload
    def register(self, obj: None = None, *, id: str | None = None) -> Callable[[T], T]: ...

    def register(self, obj: T | None = None, *, id: str | None = None) -> T | Callable[[T], T]:
        """Add ``obj`` under ``id`` (default: the object's own id); usable as a decorator.

        Registering the same object twice is harmless; another object under a taken
        id raises :class:`RegistryError`.
        """
        if obj is None:
            return lambda target: self.register(target, id=id)
        name = id or self._id_of(obj)
        if not name:
            raise RegistryError(f"{self.kind} {obj!r} has no id")
        if name in self._lazy:  # import it: registering the same object again is harmless
            self._resolve(name)
        existing = self._objects.get(name)
        if existing is not None and existing is not obj:
            raise RegistryError(f"{self.kind} id {name!r} is already taken by {_name(existing)}")
        self._objects[name] = obj
        self._order[name] = None
        return obj

    def register_lazy(self, name: str, reference: str, summary: str = "") -> None:
        """Add ``name`` for the object at ``"module:attribute"``, imported on first use
        (a built-in whose module is slow to import)."""
        if name in self._objects or name in self._lazy:
            raise RegistryError(f"{self.kind} id {name!r} is already taken")
        self._lazy[name] = reference
        self._lazy_summaries[name] = summary
        self._order[name] = None

    def unregister(self, name: str) -> None:
        """Remove ``name`` (for tests that register a throw-away object)."""
        if self._objects.pop(name, None) is None and self._lazy.pop(name, None) is None:
            raise UnknownIdError(self.kind, name, self.ids())
        self._order.pop(name, None)
        self._plugin_of.pop(name, None)

    # ------------------------------------------------------------------ plugins
    def load_plugins(self) -> None:
        """Register every entry point of :attr:`group` (once; later calls do nothing).

        A plugin that fails to load, or whose id is taken, is logged and skipped: a
        broken plugin must not break the built-ins.
        """
        if self._plugins_loaded or self.group is None:
            return
        self._plugins_loaded = True
        for entry in entry_points(group=self.group):
            try:
                obj = entry.load()
                name = self._id_of(obj) or entry.name
                if name in self._objects and self._objects[name] is obj:
                    continue
                self.register(obj, id=name)
            except Exception:  # any plugin error: log it, keep the rest
                logger.exception(
                    "could not load %s plugin %r (%s)", self.kind, entry.name, entry.value
                )
                continue
            dist = getattr(entry, "dist", None)
            self._plugin_of[name] = getattr(dist, "name", None) or entry.value

    def forget_plugins(self) -> None:
        """Drop what plugins registered and look for plugins again on the next miss
        (for tests, or after installing a package in a running interpreter)."""
        for name in self._plugin_of:
            self._objects.pop(name, None)
            self._order.pop(name, None)
        self._plugin_of.clear()
        self._plugins_loaded = False

    # ------------------------------------------------------------------ looking up
    def get(self, name: str) -> T:
        """The object registered as ``name``.

        Raises:
            UnknownIdError: no built-in and no plugin has this id (the message lists
                the known ids).
        """
        if name not in self._objects and name not in self._lazy:
            self.load_plugins()
        if name in self._lazy:
            self._resolve(name)
        try:
            return self._objects[name]
        except (KeyError, TypeError):
            raise UnknownIdError(self.kind, str(name), self.ids()) from None

    __getitem__ = get

    def _resolve(self, name: str) -> None:
        module, _, attribute = self._lazy[name].partition(":")
        obj = getattr(importlib.import_module(module), attribute)
        del self._lazy[name]
        self._objects[name] = obj

    def __contains__(self, name: object) -> bool:
        if not isinstance(name, str):
            return False
        if name in self._objects or name in self._lazy:
            return True
        self.load_plugins()
        return name in self._objects

    def __iter__(self) -> Iterator[str]:
        self.load_plugins()
        return iter(list(self._order))  # a lazy entry keeps its place once imported

    def __len__(self) -> int:
        self.load_plugins()
        return len(self._order)

    def ids(self) -> list[str]:
        """Every id, sorted (built-ins and plugins)."""
        return sorted(self)

    def available(self) -> dict[str, T]:
        """Every registered object by id, sorted (imports lazy built-ins)."""
        return {name: self.get(name) for name in self.ids()}

    def items(self) -> list[tuple[str, T]]:
        """``(id, object)`` pairs in registration order (imports lazy built-ins)."""
        return [(name, self.get(name)) for name in list(self)]

    def summary(self, name: str) -> str:
        """The one-line summary of ``name``."""
        if name in self._lazy and self._lazy_summaries.get(name):
            return self._lazy_summaries[name]
        return self._summary_of(self.get(name))

    def params(self, name: str) -> Mapping[str, Param]:
        """The parameters ``name`` declares (name -> :class:`~mrexplore.params.Param`)."""
        return self._params_of(self.get(name))

    def resolve_params(
        self, name: str, given: Mapping[str, Any], option: str = "--set"
    ) -> dict[str, Any]:
        """``name``'s parameter defaults overridden by ``given``, converted and checked
        (:func:`mrexplore.params.resolve_params`)."""
        return resolve_params(
            self.params(name), given, owner=f"{self.kind} {name!r}", option=option
        )

    def entries(self) -> list[Entry[T]]:
        """Every entry, sorted by id, with its summary, parameters and plugin origin."""
        return [
            Entry(name, obj, self.summary(name), self._params_of(obj), self._plugin_of.get(name))
            for name, obj in self.available().items()
        ]

    def __repr__(self) -> str:
        return f"Registry({self.kind!r}, group={self.group!r}, ids={list(self._objects)})"


def _name(obj: object) -> str:
    return getattr(obj, "__qualname__", None) or repr(obj)
