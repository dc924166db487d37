"""Coordination strategies, one module per method, and their registry.

The built-in strategies are registered lazily: a strategy's module (and what it
needs, such as networkx or scipy.optimize) is imported the first time its id is
looked up, so a run imports only the strategy it runs. Listing the registry
(``mrexplore strategies``) imports them all. The classes can still be imported
from here (``from mrexplore.strategies import Burgard``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

from mrexplore.strategies.base import (
    REPLAN_PARAMS,
    Decision,
    FrontierStrategy,
    Param,
    RobotView,
    Strategy,
)
from mrexplore.strategies.registry import (
    STRATEGIES,
    available_strategies,
    get_strategy,
    make_strategy,
    register,
)

if TYPE_CHECKING:
    from mrexplore.strategies.burgard import Burgard
    from mrexplore.strategies.frontier_baselines import NearestFrontier, RandomFrontier
    from mrexplore.strategies.kme import Kme
    from mrexplore.strategies.market_occupancy import MarketOccupancy
    from mrexplore.strategies.meier_polygon import MeierPolygon
    from mrexplore.strategies.sheng_bidding import ShengBidding
    from mrexplore.strategies.simmons import Simmons
    from mrexplore.strategies.vazquez_network import VazquezNetwork
    from mrexplore.strategies.zlot_market import ZlotMarket

BUILT_IN: dict[str, tuple[str, str]] = {
    "random-frontier": ("frontier_baselines", "RandomFrontier"),
    "nearest-frontier": ("frontier_baselines", "NearestFrontier"),
    "burgard": ("burgard", "Burgard"),
    "simmons": ("simmons", "Simmons"),
    "zlot-market": ("zlot_market", "ZlotMarket"),
    "sheng-bidding": ("sheng_bidding", "ShengBidding"),
    "vazquez-network": ("vazquez_network", "VazquezNetwork"),
    "kme": ("kme", "Kme"),
    "market-occupancy": ("market_occupancy", "MarketOccupancy"),
    "meier-polygon": ("meier_polygon", "MeierPolygon"),
}
"""The built-in strategies: id -> (module in this package, class), in registration
order. Each class's ``id`` is its key here (a test checks it)."""

_CLASS_MODULES = {class_name: module for module, class_name in BUILT_IN.values()}

for _id, (_module, _class_name) in BUILT_IN.items():
    STRATEGIES.register_lazy(_id, f"{__name__}.{_module}:{_class_name}")


def __getattr__(name: str) -> Any:
    """``from mrexplore.strategies import Burgard``: import the class's module now."""
    module = _CLASS_MODULES.get(name)
    if module is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    import importlib

    return getattr(importlib.import_module(f"{__name__}.{module}"), name)


__all__ = [
    "BUILT_IN",
    "REPLAN_PARAMS",
    "Burgard",
    "Decision",
    "FrontierStrategy",
    "Kme",
    "MarketOccupancy",
    "MeierPolygon",
    "NearestFrontier",
    "Param",
    "RandomFrontier",
    "RobotView",
    "ShengBidding",
    "Simmons",
    "Strategy",
    "VazquezNetwork",
    "ZlotMarket",
    "available_strategies",
    "get_strategy",
    "make_strategy",
    "register",
]
