"""The strategy registry: ids (part of the public contract) to classes.

Built-in strategies register here (``mrexplore.strategies`` registers them lazily:
a strategy's module is imported on the first lookup of its id); third-party packages
add theirs through the entry-point group ``mrexplore.strategies`` (each entry point
names a :class:`~mrexplore.strategies.base.Strategy` subclass), loaded on the first
lookup of an id that is not built in, or on the first listing. :data:`STRATEGIES` is a
:class:`mrexplore.registry.Registry`; the functions below are its historical names.
"""

from __future__ import annotations

from typing import Any

from mrexplore.registry import Registry
from mrexplore.strategies.base import Strategy

ENTRY_POINT_GROUP = "mrexplore.strategies"

STRATEGIES: Registry[type[Strategy]] = Registry("strategy", ENTRY_POINT_GROUP)
"""Every strategy class by id."""


def register(cls: type[Strategy]) -> type[Strategy]:
    """Add a strategy class under its ``id``; usable as a class decorator."""
    return STRATEGIES.register(cls)


def get_strategy(name: str) -> type[Strategy]:
    """The strategy class registered as ``name`` (:class:`~mrexplore.errors.UnknownIdError`
    if there is none)."""
    return STRATEGIES.get(name)


def available_strategies() -> dict[str, type[Strategy]]:
    """Every registered strategy, by id, sorted."""
    return STRATEGIES.available()


def make_strategy(name: str, robot_id: int, n_robots: int, params: dict[str, Any]) -> Strategy:
    """One strategy object for one robot."""
    return get_strategy(name)(robot_id, n_robots, **params)
