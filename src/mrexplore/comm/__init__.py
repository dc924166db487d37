"""Communication: messages, the byte model, communication models and map sharing."""

from mrexplore.comm.bytes import BROADCAST, HEADER_BYTES
from mrexplore.comm.ledger import ByteLedger
from mrexplore.comm.messages import Message
from mrexplore.comm.models import COMM_MODELS, CommModel, Unlimited, make_comm_model
from mrexplore.comm.sharing import (
    SHARING,
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
    "ByteLedger",
    "CommModel",
    "FullSharing",
    "MapSharing",
    "Message",
    "NoSharing",
    "Observation",
    "Unlimited",
    "make_comm_model",
    "make_sharing",
]
