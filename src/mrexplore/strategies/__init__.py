"""Coordination strategies, one module per method, and their registry."""

from mrexplore.strategies.base import (
    REPLAN_PARAMS,
    Decision,
    FrontierStrategy,
    Param,
    RobotView,
    Strategy,
)
from mrexplore.strategies.burgard import Burgard
from mrexplore.strategies.frontier_baselines import NearestFrontier, RandomFrontier
from mrexplore.strategies.kme import Kme
from mrexplore.strategies.market_occupancy import MarketOccupancy
from mrexplore.strategies.meier_polygon import MeierPolygon
from mrexplore.strategies.registry import (
    available_strategies,
    get_strategy,
    make_strategy,
    register,
)
from mrexplore.strategies.sheng_bidding import ShengBidding
from mrexplore.strategies.simmons import Simmons
from mrexplore.strategies.vazquez_network import VazquezNetwork
from mrexplore.strategies.zlot_market import ZlotMarket

for _cls in (
    RandomFrontier,
    NearestFrontier,
    Burgard,
    Simmons,
    ZlotMarket,
    ShengBidding,
    VazquezNetwork,
    Kme,
    MarketOccupancy,
    MeierPolygon,
):
    register(_cls)

__all__ = [
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
