"""Typed parameters with units, ranges and defaults, declared once in code.

Every registered object that takes parameters (a strategy, a communication model)
declares them as a mapping of names to :class:`Param`; the registry
(:mod:`mrexplore.registry`) lists them, and :func:`resolve_params` turns what a user
typed (``--set key=value``, ``--comm key=value``) into checked values.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Generic, TypeVar, overload

from mrexplore.errors import ScenarioError

T = TypeVar("T")


@dataclass(frozen=True)
class Param(Generic[T]):
    """One parameter: default, unit, meaning, the paper's symbol and valid range.

    Declared as a class attribute of a strategy, it is also how the strategy reads the
    value it runs with: ``self.beta`` is the (converted, range-checked) ``beta`` of
    this robot's strategy object, typed like the default. A class's parameters, in
    order, are those its body declares, then those of its bases
    (:attr:`Strategy.params`).

    The range is declared with keywords: ``low`` and ``high`` bound numbers
    (inclusive unless ``low_open`` / ``high_open``), ``finite=False`` lets a float
    be infinite (within the bounds; NaN is never valid), ``choices`` lists the
    values of a text parameter. :meth:`convert` refuses anything outside. The tables
    in the docs are rendered from these declarations (:mod:`mrexplore.strategies.doc`).

    >>> Param(1.0, low=0).describe()
    'a finite number >= 0'
    >>> Param(0.5, low=0, high=1, low_open=True).describe()
    'a finite number in (0, 1]'
    >>> Param(0.0, low=0, finite=False).describe()
    'a number >= 0 or inf'
    >>> Param(2, low=1).describe()
    'an integer >= 1'
    """

    default: T
    unit: str = ""
    help: str = ""
    symbol: str = ""
    low: float | None = field(default=None, kw_only=True)
    high: float | None = field(default=None, kw_only=True)
    low_open: bool = field(default=False, kw_only=True)
    high_open: bool = field(default=False, kw_only=True)
    finite: bool = field(default=True, kw_only=True)
    choices: tuple[str, ...] = field(default=(), kw_only=True)
    note: str = field(default="", kw_only=True)
    """The meaning in full for the parameter tables (paper values, our readings); ``help``,
    the short form that error messages quote, when empty."""

    def __set_name__(self, owner: type, name: str) -> None:
        object.__setattr__(self, "_name", name)  # frozen: the name is set once, here

    @overload
    def __get__(self, strategy: None, owner: type | None = None) -> Param[T]: ...
    @overload
    def __get__(self, strategy: object, owner: type | None = None) -> T: ...
    def __get__(self, strategy: object, owner: type | None = None) -> Param[T] | T:
        """On a class, the declaration; on a strategy object, the value it runs with."""
        if strategy is None:
            return self
        value: T = strategy.p[self.__dict__["_name"]]  # type: ignore[attr-defined]  # a Strategy
        return value

    def with_default(self, default: T) -> Param[T]:
        """The same parameter with another default (a strategy that departs from a
        shared rule)."""
        return dataclasses.replace(self, default=default)

    def describe(self) -> str:
        """The valid values in words: ``'an integer >= 0'``, ``'one of grid, rrt'``, ..."""
        kind = type(self.default)
        if kind is bool:
            return "true or false"
        if kind is str:
            return f"one of {', '.join(self.choices)}" if self.choices else "text"
        noun = "an integer" if kind is int else "a finite number" if self.finite else "a number"
        low, high = _bound(self.low), _bound(self.high)
        if self.low is not None and self.high is not None:
            opening = "(" if self.low_open else "["
            closing = ")" if self.high_open else "]"
            bounds = f" in {opening}{low}, {high}{closing}"
        elif self.low is not None:
            bounds = f" {'>' if self.low_open else '>='} {low}"
        elif self.high is not None:
            bounds = f" {'<' if self.high_open else '<='} {high}"
        else:
            bounds = ""
        infinite = " or inf" if kind is float and not self.finite and self.high is None else ""
        return noun + bounds + infinite

    def accepts(self, value: Any) -> bool:
        """Whether ``value`` (already of the default's type) lies in the declared range."""
        kind = type(self.default)
        if kind is bool:
            return isinstance(value, bool)
        if kind is str:
            return isinstance(value, str) and (not self.choices or value in self.choices)
        number = value if isinstance(value, int) else float(value)
        if isinstance(number, float) and (
            math.isnan(number) or (self.finite and math.isinf(number))
        ):
            return False
        if self.low is not None and (number < self.low or (self.low_open and number == self.low)):
            return False
        return self.high is None or not (
            number > self.high or (self.high_open and number == self.high)
        )

    def convert(self, name: str, value: Any, option: str = "--set") -> Any:
        """Convert a value (possibly a ``--set`` string) to the default's type and check
        it against the declared range.

        Raises:
            ScenarioError: the value does not convert, or lies outside the range; the
                message names ``option name=value``, the valid range and the meaning.
        """
        converted = self._to_kind(value)
        if converted is None:
            raise ScenarioError(
                f"{option} {name}={value}: expected {self.describe()} ({self.help or name})"
            )
        if not self.accepts(converted):
            raise ScenarioError(
                f"{option} {name}={value}: must be {self.describe()} ({self.help or name})"
            )
        return converted

    def _to_kind(self, value: Any) -> Any:
        """``value`` as the default's type, or ``None`` if it does not convert."""
        kind: type[Any] = type(self.default)
        if isinstance(value, kind) and not (kind is int and isinstance(value, bool)):
            return value
        try:
            if kind is bool:
                if isinstance(value, str):
                    lowered = value.strip().lower()
                    if lowered in {"1", "true", "yes", "on"}:
                        return True
                    if lowered in {"0", "false", "no", "off"}:
                        return False
                    return None
                return bool(value)
            if kind is int:
                if isinstance(value, str):
                    try:
                        return int(value)
                    except ValueError:
                        pass
                as_float = float(value)
                return int(as_float) if as_float.is_integer() else None
            if kind is float:
                return float(value)
            return kind(value)
        except (TypeError, ValueError, OverflowError):
            return None


def _bound(value: float | None) -> str:
    """A bound as the user would type it: ``0``, ``0.5``, ``inf``."""
    return "" if value is None else f"{value:g}"


def resolve_params(
    params: Mapping[str, Param], given: Mapping[str, Any], *, owner: str, option: str = "--set"
) -> dict[str, Any]:
    """The defaults of ``params`` overridden by ``given``, converted and range-checked.

    ``owner`` names what takes the parameters in messages (``"strategy 'burgard'"``),
    ``option`` the command-line option that sets them.

    >>> resolve_params({"k": Param(2, low=1)}, {"k": "3"}, owner="model 'm'")
    {'k': 3}

    Raises:
        ScenarioError: an unknown name, or a value that does not convert or lies
            outside its range.
    """
    unknown = sorted(set(given) - set(params))
    if unknown:
        has = ", ".join(sorted(params)) or "no parameters"
        raise ScenarioError(f"{option} {unknown[0]}: {owner} has no such parameter; it has: {has}")
    return {
        name: spec.convert(name, given[name], option) if name in given else spec.default
        for name, spec in params.items()
    }
