"""The byte model: how many bytes every message type costs on the wire.

This is the one place where message sizes are defined; every message the
simulator sends gets its ``size_bytes`` from a function here, so the byte counts
in ``result.json`` are exact consequences of this table.

Every message carries a header::

    type      uint8    message type code
    sender    uint16   robot id of the sender
    dest      uint16   robot id of the receiver, 0xFFFF = broadcast to the sub-network
    length    uint16   payload length in bytes
    ---------------------------------------------
    HEADER_BYTES = 7

Payload items (all integers little-endian, coordinates are grid cells):

=====================  ===========================================  =======
item                   fields                                        bytes
=====================  ===========================================  =======
cell update            row uint16, col uint16, state uint8            5
position               robot uint16, row uint16, col uint16           6
target announcement    robot uint16, row uint16, col uint16           6
status / request       robot uint16, row uint16, col uint16,          8
                       flags uint8, reserved uint8
bid                    robot uint16, row uint16, col uint16,          10
                       value float32
sequence-number entry  robot uint16, seq uint32                        6
polygon point          x int32, y int32, id uint32                     12
laser scan             n_beams x range uint16                          2 n
frontier point         x float32, y float32                            8
weight W_ij            float32                                         4
=====================  ===========================================  =======

Fields of the polygon packages (``polygon`` sharing, Meier et al. §3; layouts in
:mod:`mrexplore.comm.polygon_packages`): sequence number uint32 (4), item count
uint16 (2), flags uint8 (1), point id uint32 (4), polygon id uint32 (4), layer
uint8 (1). Sheng's map deltas (``sheng-sync``) carry discoverer uint16 + sequence
number uint32 (one sequence-number entry, 6) before their cells.

A broadcast is one transmission: its bytes are counted once per hop it is sent
on, not once per receiver (a radio broadcast reaches every robot in range).
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

HEADER_BYTES = 7
CELL_UPDATE_BYTES = 5
POSITION_BYTES = 6
TARGET_BYTES = 6
STATUS_BYTES = 8
BID_BYTES = 10
SEQUENCE_ENTRY_BYTES = 6
POLYGON_POINT_BYTES = 12
SCAN_BEAM_BYTES = 2
FRONTIER_POINT_BYTES = 8
WEIGHT_BYTES = 4

SEQ_BYTES = 4
COUNT_BYTES = 2
FLAGS_BYTES = 1
POINT_ID_BYTES = 4
POLYGON_ID_BYTES = 4
LAYER_BYTES = 1

BROADCAST = 0xFFFF


def cell_updates_size(n_cells: int) -> int:
    """Bytes of a message carrying ``n_cells`` cell updates.

    >>> cell_updates_size(10)
    57
    """
    return HEADER_BYTES + CELL_UPDATE_BYTES * n_cells


def float32_on_wire(values: npt.ArrayLike) -> npt.NDArray[np.float32]:
    """``values`` as the float32 a message carries them in.

    A finite value beyond float32's range is sent as its largest finite value of that
    sign, so a huge but valid weight never arrives as an infinity (nor with an
    overflow warning); infinities and NaN stay what they are.

    >>> float32_on_wire([1.5, -1e300, float("inf")]).tolist()
    [1.5, -3.4028234663852886e+38, inf]
    """
    array = np.asarray(values, dtype=np.float64)
    top = float(np.finfo(np.float32).max)
    return np.where(np.isfinite(array), np.clip(array, -top, top), array).astype(np.float32)


def fixed_size(payload_bytes: int) -> int:
    """Bytes of a message with a fixed payload of ``payload_bytes``."""
    return HEADER_BYTES + payload_bytes
