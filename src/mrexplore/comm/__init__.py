"""Communication: messages, the byte model, communication models and map sharing."""

from mrexplore.comm.bytes import BROADCAST, HEADER_BYTES
from mrexplore.comm.channels import Channel, Delayed, Lossy, Perfect
from mrexplore.comm.ledger import ByteLedger
from mrexplore.comm.links import AllLinks, LinkModel, RangeLinks, components
from mrexplore.comm.messages import Message
from mrexplore.comm.models import CommModel, Network, Unlimited, make_network
from mrexplore.comm.sharing import (
    SHARING,
    BroadcastSharing,
    FullSharing,
    MapSharing,
    NoSharing,
    Observation,
    make_sharing,
)

__all__ = [
    "BROADCAST",
    "HEADER_BYTES",
    "SHARING",
    "AllLinks",
    "BroadcastSharing",
    "ByteLedger",
    "Channel",
    "CommModel",
    "Delayed",
    "FullSharing",
    "LinkModel",
    "Lossy",
    "MapSharing",
    "Message",
    "Network",
    "NoSharing",
    "Observation",
    "Perfect",
    "RangeLinks",
    "Unlimited",
    "components",
    "make_network",
    "make_sharing",
]

from mrexplore.comm.polygon import PolygonSharing  # registers after sharing
from mrexplore.comm.sheng_sync import ShengSync  # registers after sharing

SHARING["sheng-sync"] = ShengSync
SHARING["polygon"] = PolygonSharing
