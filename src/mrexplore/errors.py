"""Exceptions raised by mrexplore.

Every problem a user can fix by changing their input raises a subclass of
:class:`MrexploreInputError`; the CLI turns those into one line on stderr and
exit status 2. Anything else escaping the library is an internal error.
"""

from __future__ import annotations


class MrexploreError(Exception):
    """Base class of every exception mrexplore raises on purpose."""


class MrexploreInputError(MrexploreError, ValueError):
    """Bad input: a file, an option or a parameter the user can correct."""


class MapFileError(MrexploreInputError):
    """A map file is missing, unreadable or malformed.

    The message always starts with the file's path.
    """

    def __init__(self, path: object, problem: str) -> None:
        self.path = str(path)
        self.problem = problem
        super().__init__(f"map file {self.path}: {problem}")


class ScenarioError(MrexploreInputError):
    """A scenario parameter is invalid (robot count, range, start cell, ...)."""


class UnknownIdError(MrexploreInputError):
    """An id was looked up in a registry that does not hold it."""

    def __init__(self, kind: str, name: str, known: list[str]) -> None:
        self.kind = kind
        self.name = name
        super().__init__(f"unknown {kind} {name!r}; known: {', '.join(sorted(known))}")


class StrategyError(MrexploreError):
    """A strategy broke its contract (returned an illegal target, ...)."""


class CommModelError(MrexploreError):
    """A communication model broke its protocol (delivered beyond its sender's
    sub-network, twice, ...)."""


class UnreachableTargetError(MrexploreError, ValueError):
    """A path was asked for to a cell that the distance field did not reach."""


class RunDirError(MrexploreInputError):
    """An output folder cannot be used for a run (without ``--force``)."""


class EngineError(MrexploreInputError):
    """An engine cannot be used: unknown name, missing extra, unreachable cluster."""


class SweepError(MrexploreInputError):
    """A sweep file or sweep option is invalid."""


class StoreError(MrexploreInputError):
    """A results folder is missing, not a store, or a query is invalid."""


class RegistryError(MrexploreError):
    """Registering went wrong: no id, or an id that another object already holds."""


class PolygonLimitError(MrexploreError):
    """A package would need a count beyond its uint16 field."""
