"""Per-hop channels: when, and whether, one transmission reaches each receiver.

Channels compose by wrapping: ``Lossy(Delayed(Perfect(), latency=3), p=0.2, rng)``
delivers after 3 ticks and loses each reception with probability 0.2.
"""

from __future__ import annotations

from abc import ABC, abstractmethod

import numpy as np


class Channel(ABC):
    """Decides the arrival tick of each reception of one hop (``None`` = lost)."""

    @abstractmethod
    def arrivals(self, receivers: list[int], tick_sent: int) -> list[int | None]:
        """Arrival tick for each receiver of a hop completed at ``tick_sent``."""

    @abstractmethod
    def describe(self) -> str:
        """A short description for reports."""


class Perfect(Channel):
    """Every reception arrives at the next tick."""

    def arrivals(self, receivers: list[int], tick_sent: int) -> list[int | None]:
        return [tick_sent + 1] * len(receivers)

    def describe(self) -> str:
        return "perfect"


class Delayed(Channel):
    """Receptions arrive ``latency`` ticks after the hop was sent (``latency >= 1``)."""

    def __init__(self, inner: Channel, latency: int) -> None:
        if latency < 1:
            raise ValueError("latency must be at least one tick")
        self.inner = inner
        self.latency = latency

    def arrivals(self, receivers: list[int], tick_sent: int) -> list[int | None]:
        extra = self.latency - 1
        return [None if t is None else t + extra for t in self.inner.arrivals(receivers, tick_sent)]

    def describe(self) -> str:
        return f"latency {self.latency} > {self.inner.describe()}"


class Lossy(Channel):
    """Each reception is lost independently with probability ``p``."""

    def __init__(self, inner: Channel, p: float, rng: np.random.Generator) -> None:
        if not 0.0 <= p <= 1.0:
            raise ValueError("loss probability must be in [0, 1]")
        self.inner = inner
        self.p = p
        self.rng = rng

    def arrivals(self, receivers: list[int], tick_sent: int) -> list[int | None]:
        inner = self.inner.arrivals(receivers, tick_sent)
        if self.p == 0.0 or not receivers:
            return inner
        lost = self.rng.random(len(receivers)) < self.p
        return [None if gone else t for t, gone in zip(inner, lost, strict=True)]

    def describe(self) -> str:
        return f"loss {self.p:g} > {self.inner.describe()}"
