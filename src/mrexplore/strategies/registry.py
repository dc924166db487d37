"""The strategy registry: ids (part of the public contract) to classes.

Built-in strategies register here; third-party packages add theirs through the
entry-point group ``mrexplore.strategies`` (each entry point names a
:class:`~mrexplore.strategies.base.Strategy` subclass), loaded on first lookup.
"""

from __future__ import annotations

import logging
from importlib.metadata import entry_points
from typing import Any

from mrexplore.errors import UnknownIdError
from mrexplore.strategies.base import Strategy

logger = logging.getLogger(__name__)

ENTRY_POINT_GROUP = "mrexplore.strategies"

_REGISTRY: dict[str, type[Strategy]] = {}
_plugins_loaded = False


def register(cls: type[Strategy]) -> type[Strategy]:
    """Add a strategy class under its ``id``; usable as a class decorator."""
    if not cls.id:
        raise ValueError(f"{cls.__name__} has no id")
    existing = _REGISTRY.get(cls.id)
    if existing is not None and existing is not cls:
        raise ValueError(f"strategy id {cls.id!r} is already taken by {existing.__name__}")
    _REGISTRY[cls.id] = cls
    return cls


def _load_plugins() -> None:
    global _plugins_loaded
    if _plugins_loaded:
        return
    _plugins_loaded = True
    for entry in entry_points(group=ENTRY_POINT_GROUP):
        try:
            cls = entry.load()
            register(cls)
        except Exception:  # a broken plugin must not break the built-ins
            logger.exception("could not load strategy plugin %s", entry.name)


def get_strategy(name: str) -> type[Strategy]:
    """The strategy class registered as ``name``."""
    if name not in _REGISTRY:
        _load_plugins()
    try:
        return _REGISTRY[name]
    except KeyError:
        raise UnknownIdError("strategy", name, list(_REGISTRY)) from None


def available_strategies() -> dict[str, type[Strategy]]:
    """Every registered strategy, by id, sorted."""
    _load_plugins()
    return dict(sorted(_REGISTRY.items()))


def make_strategy(name: str, robot_id: int, n_robots: int, params: dict[str, Any]) -> Strategy:
    """One strategy object for one robot."""
    return get_strategy(name)(robot_id, n_robots, **params)
