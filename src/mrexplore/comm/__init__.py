"""Communication: messages, the byte model, communication models and map sharing."""

from mrexplore.comm.bytes import BROADCAST, HEADER_BYTES
from mrexplore.comm.channels import Channel, Delayed, Lossy, Perfect
from mrexplore.comm.ledger import ByteLedger
from mrexplore.comm.links import AllLinks, LinkModel, RangeLinks, components
from mrexplore.comm.messages import Message
from mrexplore.comm.models import (
    COMM_MODELS,
    CommModel,
    CommSetup,
    CommStats,
    Network,
    make_comm_model,
    make_network,
)
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
    "COMM_MODELS",
    "HEADER_BYTES",
    "SHARING",
    "AllLinks",
    "BroadcastSharing",
    "ByteLedger",
    "Channel",
    "CommModel",
    "CommSetup",
    "CommStats",
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
    "components",
    "make_comm_model",
    "make_network",
    "make_sharing",
]

# Mechanisms in modules of their own, imported on first use (a run imports only its own).
SHARING.register_lazy("sheng-sync", "mrexplore.comm.sheng_sync:ShengSync")
SHARING.register_lazy("polygon", "mrexplore.comm.polygon:PolygonSharing")
