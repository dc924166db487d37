r"""``polygon``: share polygonal approximations of the robots' maps, incrementally.

D. Meier, C. Stachniss, W. Burgard, "Coordinating multiple robots during
exploration under communication with limited bandwidth", Proc. European
Conference on Mobile Robots (ECMR), 2005, §3 (the approximation and its
incremental update) and §5 (split rate, package types, approximation error).
The step-by-step mapping of the paper to this code, and every interpretation,
is in ``docs/sharing/polygon.md``.

What each robot keeps
=====================

* its **own observed map**: the cells it sensed itself (true states, from the
  :class:`~mrexplore.comm.sharing.Observation` objects given to
  :meth:`PolygonSharing.on_observe`), never what it received;
* a **polygonal approximation** of it in two layers: closed polygons along the
  contours of the observed area (free or occupied cells; the outer borders and
  the borders of unobserved holes) and along the contours of the observed
  obstacles. Vertices are cell centres on those contours;
* for every other robot, that robot's polygons as rebuilt from its packages.

Rasterising a layer marks the cells inside its polygons (even-odd rule: a hole
cancels its outer border, so inner polygons override outer ones as in the
paper) plus the cells its edges pass through. A map is read as occupied over
free over unknown: obstacle-layer cells are ``OCCUPIED``, other observed-layer
cells ``FREE``, the rest ``UNKNOWN``.

The update (paper §3)
=====================

When a robot's observed map changes, the contours of the changed layer are
traced again (:func:`~mrexplore.comm.polygon_kernels.trace_contours`). A
contour identical to one of the previous step keeps its polygon untouched. For
the others:

1. *Case 1, vanished points*: a vertex that no longer lies on a contour is
   removed; its former neighbours become connected (package ``VP``).
2. *Case 3, broken boundaries*: each surviving vertex is labelled with the
   contour it lies on; the vertices on one contour, in contour order, form one
   closed polygon. A polygon whose vertices now lie on several contours is
   broken into several; polygons whose contours merged are joined; a polygon
   left with one vertex is closed with the contour point farthest from it (the
   paper's "arbitrary point"). Every polygon whose vertex list changed other
   than by removals is re-sent as runs of known vertices (package ``B``).
3. *Case 3, emerged points*: a contour on which no old vertex lies gets a new
   polygon of two vertices, its first point and the point farthest from it
   (package ``EP``).
4. *Case 2 and refinement*: Douglas-Peucker by edge splits. For every edge the
   contour points between its two vertices are compared with the segment; the
   edge whose farthest point deviates most, over all polygons of both layers,
   is split at that point (package ``ES``) while the deviation exceeds
   ``epsilon`` and the split budget allows.

Split budget: a token bucket that starts empty, gains ``split_rate /
ticks_per_second`` splits every tick and holds at most that plus one (0.1
splits/s at one tick per second: a split at ticks 9, 19, 29, ... while
refinement is needed), so no more than ``split_rate * T + 1`` splits happen in
any ``T`` seconds; unused splits beyond the bucket's depth are lost. Closing
points of case 3 are part of the update and do not use the budget. Splits run
in :meth:`~PolygonSharing.on_observe` and also in :meth:`~PolygonSharing.on_tick`,
so a robot that stops sensing new cells keeps refining.

Packages
========

Message types are the paper's package names (§5.3, Table 1); the byte layout is
in :mod:`mrexplore.comm.polygon_packages` (point = ``x int32, y int32, id
uint32``, 12 bytes):

* ``VP`` (vanished points): ids of vertices that left the approximation.
* ``B`` (broken boundary): polygons re-linked from surviving vertices (a
  boundary that split, boundaries that merged, a re-ordered or re-closed
  polygon); with the resync flag, the sender's whole map, every point in full.
* ``EP`` (emerged points): polygons of newly appeared boundaries (new obstacles,
  new holes).
* ``ES`` (edge split): a new vertex and the vertex after which it goes.
* ``TPT`` (target point transmission) is the paper's fifth type but carries a
  robot's chosen target, which is the coordination strategy's business; this
  mechanism neither sends nor consumes it, and it is not in
  :attr:`PolygonSharing.message_types` so that the simulator hands ``TPT``
  messages to the strategy (:data:`~mrexplore.comm.polygon_packages.TPT`).

All packages are broadcast. Each call of ``on_observe`` or ``on_tick`` sends a
robot's changes as at most one message of each type, in the order ``VP``,
``B``, ``EP``, ``ES`` (then a resync ``B`` if one is due); sequence numbers
follow that order, which is the order a receiver applies them in.

Loss and latency
================

Every package carries a per-sender sequence number (uint32, 1, 2, ...). A
receiver applies a sender's packages in sequence order; a package whose number
is not the next one reveals a gap (lost or overtaken packages), after which the
receiver ignores that sender's increments, keeping the polygons it had, until a
full resync arrives. Late packages (numbers already passed) are dropped. On a
gap the receiver sends the sender a resync request (``RQ``: header + the
sequence number it saw, 11 bytes; repeated after 10 more ignored packages if the
resync does not come). A sender broadcasts a full resync (``B`` with the resync
flag, all its polygons) at the tick after a request, whenever its sub-network
gains robots it could not reach at the previous tick, and, if ``resync_every``
> 0, periodically.

Receivers
=========

A receiver rasterises the union of the polygons of all senders (per sender and
layer by the even-odd rule, then occupied over free over unknown across
senders) and writes the result into its belief only at cells it has not
observed itself. Only the boxes of cells that the applied packages can have
changed are composed again, one box per sender; receivers that applied the
same packages share one copy of a sender's polygons and its rasters
(:mod:`mrexplore.comm.polygon_inbound`). Cells outside every received polygon
are written ``UNKNOWN``, so a coarse approximation that is later refined gives
its cells back. :meth:`~PolygonSharing.on_receive_all` returns the number of belief cells
whose value changed.

Parameters
==========

=====  ====================  =======  ========  =============================================
paper  name                  default  unit      meaning
=====  ====================  =======  ========  =============================================
SR     ``split_rate``        1.0      splits/s  upper bound on Douglas-Peucker edge splits per
                                                second (the paper uses 0.04 to 25)
\-     ``ticks_per_second``  1.0      ticks/s   one simulated second is this many ticks;
                                                1.0: one tick is one second
\-     ``epsilon``           0        cells     an edge is split only while a contour point
                                                between its vertices lies farther than this
                                                (§5.1: no split once "the approximation
                                                error is equal to zero")
\-     ``resync_every``      0        ticks     period of full resyncs; 0 = only when the
                                                sub-network gains robots
=====  ====================  =======  ========  =============================================

``split_rate`` may be ``math.inf`` (refine every edge to ``epsilon`` at once).

Example:
    >>> import numpy as np
    >>> from mrexplore.comm.sharing import Observation
    >>> from mrexplore.grid.occupancy import FREE, OCCUPIED, new_belief
    >>> sharing = PolygonSharing(split_rate=10.0)
    >>> sharing.bind(2, (6, 6))
    >>> rows, cols = np.divmod(np.arange(36), 6)
    >>> values = np.where(cols == 5, OCCUPIED, FREE).astype(np.int8)
    >>> seen = Observation(rows, cols, values, np.ones(36, dtype=bool))
    >>> messages = sharing.on_observe(0, 0, seen, new_belief((6, 6)))
    >>> [m.type for m in messages]
    ['EP', 'ES']
    >>> belief = new_belief((6, 6))
    >>> sharing.on_receive_all(1, belief, messages)
    36
    >>> bool((belief[:, 5] == OCCUPIED).all() and (belief[:, :5] == FREE).all())
    True
    >>> sharing.approximation_error(0)
    0.0
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import numpy.typing as npt

from mrexplore.comm.bytes import BROADCAST, HEADER_BYTES, SEQ_BYTES
from mrexplore.comm.messages import Message
from mrexplore.comm.polygon_inbound import Box, MapVersion, SharedMaps, rasterise_into, union
from mrexplore.comm.polygon_kernels import (
    edge_deviation,
    edge_deviations,
    farthest_point,
    match_vertices,
    paint_box,
    trace_contours,
)
from mrexplore.comm.polygon_packages import (
    EP,
    ES,
    MAP_PACKAGE_TYPES,
    OBSERVED_LAYER,
    OBSTACLE_LAYER,
    TPT,
    VP,
    B,
    BrokenBoundary,
    EdgeSplits,
    EmergedPoints,
    Payload,
    PolygonMap,
    PolygonRecord,
    PolygonRuns,
    Resync,
    VanishedPoints,
    payload_size,
)
from mrexplore.comm.sharing import MapSharing, Observation
from mrexplore.errors import MrexploreInputError
from mrexplore.grid.occupancy import FREE, OCCUPIED, UNKNOWN, BeliefGrid

__all__ = ["EP", "ES", "TPT", "VP", "B", "PolygonSharing"]

IntArray = npt.NDArray[np.int64]
FloatArray = npt.NDArray[np.float64]
LAYERS = (OBSERVED_LAYER, OBSTACLE_LAYER)
BUDGET_SLACK = 1e-9
"""Rounding slack of the split budget (ten times 0.1 splits make a split)."""

RESYNC_REQUEST = "RQ"
"""A receiver that detected a gap asks the sender for a full resync (our addition)."""
REQUEST_AGAIN_AFTER = 10
"""Packages ignored while out of sync before a receiver repeats its request."""
ERROR_SAMPLE_EVERY = 10
"""Ticks between samples of the approximation error for its mean over the run
(``polygon_approximation_error_mean``; observation only, it changes nothing)."""


@dataclass
class _Tracked:
    """A polygon of the sender's own approximation, tied to the contour it follows.

    ``anchors[i]`` is the position on ``contour`` of vertex ``ids[i]``; edge ``i``
    runs from vertex ``i`` to vertex ``i + 1`` (cyclically) along the contour
    points in between; ``deviation[i]`` and ``farthest[i]`` are its largest
    distance (cells) and the contour position attaining it.
    """

    layer: int
    ids: IntArray
    anchors: IntArray
    contour: IntArray
    key: int
    deviation: FloatArray
    farthest: IntArray
    version: int = 0
    _xy: tuple[IntArray, npt.NDArray[np.int32]] | None = None

    def xy(self, width: int) -> npt.NDArray[np.int32]:
        # Kept while ``anchors`` is the same array (it is replaced, never written).
        if self._xy is not None and self._xy[0] is self.anchors:
            return self._xy[1]
        cells = self.contour[self.anchors]
        xy = np.stack([cells % width, cells // width], axis=1).astype(np.int32)
        self._xy = (self.anchors, xy)
        return xy

    def record(self, polygon_id: int, width: int) -> PolygonRecord:
        cells = self.contour[self.anchors]
        points = np.stack([cells % width, cells // width, self.ids], axis=1).astype(np.int64)
        return PolygonRecord(polygon_id, self.layer, points)


@dataclass
class _Inbound:
    """What a receiver holds from one sender: its copy of the map (shared with the
    receivers that applied the same packages) and where it is in the sequence."""

    version: MapVersion
    last_seq: int = 0
    in_sync: bool = True
    ignored_since_request: int = 0
    dirty: Box | None = None
    """Cells the packages applied since the last repaint changed."""

    @property
    def map(self) -> PolygonMap:
        return self.version.map


@dataclass
class _Changes:
    """Packages one tick's update produces, before they get sequence numbers."""

    vanished: list[int] = field(default_factory=list)
    broken: list[PolygonRuns] = field(default_factory=list)
    broken_points: list[tuple[int, int, int]] = field(default_factory=list)
    emerged: list[PolygonRecord] = field(default_factory=list)
    split_after: list[int] = field(default_factory=list)
    split_points: list[tuple[int, int, int]] = field(default_factory=list)


class _RobotState:
    """Per-robot protocol state: own map and polygons as a sender, inbound maps as a receiver."""

    def __init__(self, shape: tuple[int, int]) -> None:
        self.own = np.full(shape, UNKNOWN, dtype=np.int8)
        self.tracked: dict[int, _Tracked] = {}
        # Per layer: contour hashes, polygon ids and contour lengths of the tracked
        # polygons, for recognising unchanged contours.
        self.keys: list[tuple[npt.NDArray[np.uint64], IntArray, IntArray]] = [
            (np.zeros(0, dtype=np.uint64), np.zeros(0, dtype=np.int64), np.zeros(0, np.int64))
            for _ in LAYERS
        ]
        self.dirty = [False, False]
        # Per layer, (row_min, row_max, col_min, col_max) holding every cell of the
        # layer ever observed; the first observation replaces the empty extent.
        self.extent = [(shape[0], -1, shape[1], -1) for _ in LAYERS]
        self.next_point_id = 0
        self.next_polygon_id = 0
        self.version = 0
        self.seq = 0
        self.budget = 0.0
        self.budget_tick: int | None = None
        self.heap: list[tuple[float, int, int]] = []
        self.next_resync: int | None = None
        self.members: frozenset[int] | None = None
        self.error_samples: list[float] = []
        self.inbound: dict[int, _Inbound] = {}
        self.resync_requested = False

    def extend(self, layer: int, rows: IntArray, cols: IntArray) -> None:
        """Widen ``layer``'s extent to hold the cells ``rows, cols`` (not empty)."""
        row0, row1, col0, col1 = self.extent[layer]
        self.extent[layer] = (
            min(row0, int(rows.min())),
            max(row1, int(rows.max())),
            min(col0, int(cols.min())),
            max(col1, int(cols.max())),
        )

    def observed_anything(self) -> bool:
        row0, row1, col0, col1 = self.extent[OBSERVED_LAYER]
        return bool((self.own[row0 : row1 + 1, col0 : col1 + 1] != UNKNOWN).any())

    def new_point_id(self) -> int:
        self.next_point_id += 1
        return self.next_point_id - 1

    def new_polygon_id(self) -> int:
        self.next_polygon_id += 1
        return self.next_polygon_id - 1


class PolygonSharing(MapSharing):
    """Meier et al. (2005) §3: incremental polygon maps refined by rate-limited edge splits.

    Args:
        split_rate: SR, the most Douglas-Peucker edge splits per simulated second
            (``>= 0``; ``math.inf`` = no limit). Default 1.0 (the paper gives no
            default; its Table 2 uses 0.1, 1 and 10).
        ticks_per_second: simulator ticks per simulated second (``> 0``); default
            1.0, one tick is one second. Splits per tick = ``split_rate /
            ticks_per_second``.
        epsilon: Douglas-Peucker tolerance in cells (``>= 0``): edges whose
            contour points all lie within it are not split. Default 0, the paper's
            "approximation error is equal to zero" (§5.1).
        resync_every: ticks between full resyncs (``>= 0``; 0 = only when a
            robot's sub-network gains members).

    Raises:
        MrexploreInputError: a parameter out of range.

    See the module docstring for the packages and the protocol.
    """

    id = "polygon"
    message_types = MAP_PACKAGE_TYPES | {RESYNC_REQUEST}

    def __init__(
        self,
        split_rate: float = 1.0,
        ticks_per_second: float = 1.0,
        epsilon: float = 0.0,
        resync_every: int = 0,
    ) -> None:
        if not (isinstance(split_rate, int | float) and split_rate >= 0):
            raise MrexploreInputError(f"split_rate must be >= 0 splits/s, got {split_rate!r}")
        if not (isinstance(ticks_per_second, int | float) and 0 < ticks_per_second < math.inf):
            raise MrexploreInputError(
                f"ticks_per_second must be a positive number, got {ticks_per_second!r}"
            )
        if not (isinstance(epsilon, int | float) and 0 <= epsilon < math.inf):
            raise MrexploreInputError(f"epsilon must be >= 0 cells, got {epsilon!r}")
        if (
            isinstance(resync_every, bool)
            or not isinstance(resync_every, int | float)
            or not float(resync_every).is_integer()
            or resync_every < 0
        ):
            raise MrexploreInputError(
                f"resync_every must be a whole number of ticks >= 0, got {resync_every!r}"
            )
        self.split_rate = float(split_rate)
        self.ticks_per_second = float(ticks_per_second)
        self.epsilon = float(epsilon)
        self.resync_every = int(resync_every)
        self.splits_per_tick = self.split_rate / self.ticks_per_second
        self.bucket_size = self.splits_per_tick + 1.0
        self.n_robots = 0
        self.shape = (0, 0)
        self._robots: list[_RobotState] = []
        self.resyncs_sent = 0
        self.gaps_detected = 0

    # ------------------------------------------------------------------ set-up
    def bind(self, n_robots: int, shape: tuple[int, int]) -> None:
        """Start a run: ``n_robots`` robots on a grid of ``shape`` cells, nothing known."""
        super().bind(n_robots, shape)
        self._robots = [_RobotState(shape) for _ in range(n_robots)]
        self.resyncs_sent = 0
        self.gaps_detected = 0
        self._head = np.full(shape[0] * shape[1], -1, dtype=np.int64)
        self._labels = np.empty((shape[0] + 2) * (shape[1] + 2), dtype=np.int32)
        self._maps = SharedMaps(shape)

    def _state(self, robot: int) -> _RobotState:
        if not self._robots:
            raise MrexploreInputError("PolygonSharing.bind(n_robots, shape) was not called")
        return self._robots[robot]

    # ------------------------------------------------------------------ sender
    def on_observe(
        self, robot: int, tick: int, observation: Observation, belief: BeliefGrid
    ) -> list[Message]:
        """Update ``robot``'s own map and polygons; return the packages that describe the change."""
        state = self._state(robot)
        rows, cols, values = observation.rows, observation.cols, observation.values
        old = state.own[rows, cols]
        changed = old != values
        if changed.any():
            state.dirty[OBSERVED_LAYER] |= bool((old[changed] == UNKNOWN).any())
            state.dirty[OBSTACLE_LAYER] |= bool(
                ((values[changed] == OCCUPIED) | (old[changed] == OCCUPIED)).any()
            )
            state.own[rows, cols] = values
            state.extend(OBSERVED_LAYER, rows[changed], cols[changed])
            occupied = changed & (values == OCCUPIED)
            if occupied.any():
                state.extend(OBSTACLE_LAYER, rows[occupied], cols[occupied])
        changes = _Changes()
        for layer in LAYERS:
            if state.dirty[layer]:
                self._update_layer(state, layer, changes)
                state.dirty[layer] = False
        self._refine(state, tick, changes)
        messages = self._package(robot, state, tick, changes)
        if self._resync_due(state, tick):
            messages.append(self._resync(robot, state, tick))
        return messages

    def on_tick(
        self, tick: int, subnetworks: list[frozenset[int]], beliefs: Sequence[BeliefGrid]
    ) -> list[Message]:
        """Keep refining every live robot's polygons; send resyncs that are due.

        A robot resyncs when ``resync_every`` ticks have passed since its last
        resync or when its sub-network holds a robot it did not hold at the
        previous call. Robots in no sub-network (dead) are skipped.
        """
        if not self._robots:
            return []
        member_of = {robot: group for group in subnetworks for robot in group}
        messages: list[Message] = []
        for robot, state in enumerate(self._robots):
            members = member_of.get(robot)
            if members is None:
                continue
            changes = _Changes()
            self._refine(state, tick, changes)
            messages.extend(self._package(robot, state, tick, changes))
            gained = state.members is not None and bool(members - state.members)
            state.members = members
            if gained or state.resync_requested or self._resync_due(state, tick):
                state.resync_requested = False
                messages.append(self._resync(robot, state, tick))
            if tick % ERROR_SAMPLE_EVERY == 0 and state.observed_anything():
                state.error_samples.append(self.approximation_error(robot))
        return messages

    def _resync_due(self, state: _RobotState, tick: int) -> bool:
        if self.resync_every == 0:
            return False
        if state.next_resync is None:
            state.next_resync = tick + self.resync_every
        return tick >= state.next_resync

    def _resync(self, robot: int, state: _RobotState, tick: int) -> Message:
        if self.resync_every:
            state.next_resync = tick + self.resync_every
        self.resyncs_sent += 1
        width = self.shape[1]
        records = tuple(t.record(pid, width) for pid, t in sorted(state.tracked.items()))
        state.seq += 1
        payload = Resync(state.seq, records)
        return Message(B, robot, BROADCAST, payload_size(B, payload), payload, tick)

    def _package(
        self, robot: int, state: _RobotState, tick: int, changes: _Changes
    ) -> list[Message]:
        """Number and size the tick's packages, in the order receivers must apply them."""
        payloads: list[tuple[str, Payload]] = []
        if changes.vanished:
            state.seq += 1
            ids = np.asarray(changes.vanished, dtype=np.int64)
            payloads.append((VP, VanishedPoints(state.seq, ids)))
        if changes.broken:
            state.seq += 1
            new_points = np.asarray(changes.broken_points, dtype=np.int64).reshape(-1, 3)
            payloads.append((B, BrokenBoundary(state.seq, new_points, tuple(changes.broken))))
        if changes.emerged:
            state.seq += 1
            payloads.append((EP, EmergedPoints(state.seq, tuple(changes.emerged))))
        if changes.split_after:
            state.seq += 1
            after = np.asarray(changes.split_after, dtype=np.int64)
            points = np.asarray(changes.split_points, dtype=np.int64).reshape(-1, 3)
            payloads.append((ES, EdgeSplits(state.seq, after, points)))
        return [
            Message(kind, robot, BROADCAST, payload_size(kind, payload), payload, tick)
            for kind, payload in payloads
        ]

    def _update_layer(self, state: _RobotState, layer: int, changes: _Changes) -> None:
        """Re-trace one layer's contours and update its polygons (paper cases 1 and 3)."""
        width = self.shape[1]
        # Only the box holding every cell of the layer is traced (same contours).
        row0, row1, col0, col1 = state.extent[layer]
        own = state.own[row0 : row1 + 1, col0 : col1 + 1]
        mask = own != UNKNOWN if layer == OBSERVED_LAYER else own == OCCUPIED
        points, offsets, _, hashes = trace_contours(mask, self._labels, (row0, col0), width)
        lengths = np.diff(offsets)
        old_keys, old_pids, old_lengths = state.keys[layer]
        # Contours identical to a previous one keep their polygon as it is.
        unchanged = np.zeros(hashes.size, dtype=bool)
        kept_pids = np.zeros(0, dtype=np.int64)
        if old_keys.size and hashes.size:
            order = np.argsort(old_keys)
            at = np.searchsorted(old_keys, hashes, sorter=order)
            at = order[np.minimum(at, old_keys.size - 1)]
            # (A 64-bit hash and the length identify a contour; two different
            # contours of one map never share both.)
            unchanged = (old_keys[at] == hashes) & (old_lengths[at] == lengths)
            kept_pids = old_pids[at[unchanged]]
        stale = sorted(set(old_pids.tolist()) - set(kept_pids.tolist()))
        stale_tracked = [(pid, state.tracked.pop(pid)) for pid in stale]
        # Where do the vertices of the changed polygons lie now?
        if stale_tracked:
            vertex_ids = np.concatenate([t.ids for _, t in stale_tracked])
            vertex_cells = np.concatenate([t.contour[t.anchors] for _, t in stale_tracked])
            source = np.repeat(
                np.arange(len(stale_tracked), dtype=np.int64),
                [t.ids.size for _, t in stale_tracked],
            )
            polygon_offsets = np.zeros(len(stale_tracked) + 1, dtype=np.int64)
            np.cumsum([t.ids.size for _, t in stale_tracked], out=polygon_offsets[1:])
        else:
            vertex_ids = vertex_cells = source = np.zeros(0, dtype=np.int64)
            polygon_offsets = np.zeros(1, dtype=np.int64)
        eligible = ~unchanged
        on_contour = np.full(vertex_ids.size, -1, dtype=np.int64)
        at_index = np.full(vertex_ids.size, -1, dtype=np.int64)
        if vertex_ids.size:
            match_vertices(
                points,
                offsets,
                eligible,
                self._head,
                vertex_cells,
                polygon_offsets,
                on_contour,
                at_index,
            )
        survives = on_contour >= 0
        # Two vertices at the same place of the same contour: keep the first.
        if survives.any():
            slot = on_contour * (int(lengths.max()) + 1) + at_index
            alive = np.flatnonzero(survives)
            _, first = np.unique(slot[alive], return_index=True)
            duplicate = np.ones(alive.size, dtype=bool)
            duplicate[first] = False
            survives[alive[duplicate]] = False
        changes.vanished.extend(vertex_ids[~survives].tolist())
        # Positions of the survivors in their old polygons once the vanished points
        # are gone (what a receiver holds when it reads the B package).
        survivors_before = np.concatenate([[0], np.cumsum(survives)])
        reduced_position = survivors_before[:-1] - survivors_before[polygon_offsets[source]]
        reduced_length = (
            survivors_before[polygon_offsets[1:]] - survivors_before[polygon_offsets[:-1]]
        )
        # Which old polygon's id each changed contour inherits: a polygon goes on
        # the contour holding most of its surviving vertices; a contour takes the
        # id of the polygon that brings it the most.
        alive = np.flatnonzero(survives)
        heir: dict[int, int] = {}
        if alive.size:
            n_contours = hashes.size
            pair = source[alive] * n_contours + on_contour[alive]
            pairs, counts = np.unique(pair, return_counts=True)
            best_for_polygon: dict[int, tuple[int, int]] = {}
            for p, count in zip(pairs.tolist(), counts.tolist(), strict=True):
                polygon, contour = divmod(p, n_contours)
                if polygon not in best_for_polygon or count > best_for_polygon[polygon][1]:
                    best_for_polygon[polygon] = (contour, count)
            best_for_contour: dict[int, tuple[int, int]] = {}
            for polygon, (contour, count) in sorted(best_for_polygon.items()):
                pid = stale_tracked[polygon][0]
                held = best_for_contour.get(contour)
                if held is None or count > held[1] or (count == held[1] and pid < held[0]):
                    best_for_contour[contour] = (pid, count)
            heir = {contour: pid for contour, (pid, _) in best_for_contour.items()}
        # Group the surviving vertices by contour, in contour order.
        order = np.lexsort((at_index[alive], on_contour[alive]))
        alive = alive[order]
        group_contours, group_starts = np.unique(on_contour[alive], return_index=True)
        group_bounds = np.append(group_starts, alive.size)
        groups = {
            int(k): alive[group_bounds[g] : group_bounds[g + 1]]
            for g, k in enumerate(group_contours.tolist())
        }
        new_keys = [hashes[unchanged]]
        new_pids = [kept_pids]
        new_lengths = [lengths[unchanged]]
        for k in np.flatnonzero(eligible).tolist():
            contour = points[offsets[k] : offsets[k + 1]].copy()
            members = groups.get(k)
            if members is None:
                pid = state.new_polygon_id()
                anchors = np.array([0], dtype=np.int64)
                far = int(farthest_point(contour, width, 0))
                if contour[far] != contour[0]:
                    anchors = np.array([0, far], dtype=np.int64)
                ids = np.array([state.new_point_id() for _ in anchors], dtype=np.int64)
                tracked = self._track(state, layer, ids, anchors, contour, int(hashes[k]))
                changes.emerged.append(tracked.record(pid, width))
            else:
                ids = vertex_ids[members]
                anchors = at_index[members]
                inherited = heir.get(k)
                resend = inherited is None
                if inherited is None:
                    pid = state.new_polygon_id()
                else:
                    pid = inherited
                    resend = not _same_cycle(source[members], reduced_position[members])
                sources = source[members]
                positions = reduced_position[members]
                if ids.size == 1:
                    far = int(farthest_point(contour, width, int(anchors[0])))
                    if contour[far] != contour[anchors[0]]:
                        new_id = state.new_point_id()
                        cell = int(contour[far])
                        point = (cell % width, cell // width, new_id)
                        if resend:
                            changes.broken_points.append(point)
                        else:
                            changes.split_after.append(int(ids[0]))
                            changes.split_points.append(point)
                        ids = np.array([ids[0], new_id], dtype=np.int64)
                        anchors = np.array([anchors[0], far], dtype=np.int64)
                        sources = np.array([sources[0], -1], dtype=np.int64)
                        positions = np.array([positions[0], -1], dtype=np.int64)
                tracked = self._track(state, layer, ids, anchors, contour, int(hashes[k]))
                if resend:
                    runs = _runs(ids, sources, positions, reduced_length)
                    changes.broken.append(PolygonRuns(pid, layer, runs))
            state.tracked[pid] = tracked
            self._push(state, pid, tracked)
            new_keys.append(hashes[k : k + 1])
            new_pids.append(np.array([pid], dtype=np.int64))
            new_lengths.append(lengths[k : k + 1])
        state.keys[layer] = (
            np.concatenate(new_keys),
            np.concatenate(new_pids),
            np.concatenate(new_lengths),
        )

    def _track(
        self,
        state: _RobotState,
        layer: int,
        ids: IntArray,
        anchors: IntArray,
        contour: IntArray,
        key: int,
    ) -> _Tracked:
        deviation, farthest = edge_deviations(contour, self.shape[1], anchors)
        state.version += 1
        return _Tracked(layer, ids, anchors, contour, key, deviation, farthest, state.version)

    def _push(self, state: _RobotState, pid: int, tracked: _Tracked) -> None:
        worst = float(tracked.deviation.max()) if tracked.deviation.size else 0.0
        if worst > self.epsilon:
            heapq.heappush(state.heap, (-worst, pid, tracked.version))

    def _refine(self, state: _RobotState, tick: int, changes: _Changes) -> None:
        """Case 2: split the worst edges while the budget lasts (Douglas-Peucker)."""
        # Each tick since the last call adds a tick's splits (the first call: one tick).
        elapsed = 1 if state.budget_tick is None else tick - state.budget_tick
        if elapsed > 0:
            state.budget = min(self.bucket_size, state.budget + elapsed * self.splits_per_tick)
            state.budget_tick = tick
        width = self.shape[1]
        while state.budget >= 1.0 - BUDGET_SLACK and state.heap:
            _, pid, version = state.heap[0]
            tracked = state.tracked.get(pid)
            if tracked is None or tracked.version != version:
                heapq.heappop(state.heap)
                continue
            heapq.heappop(state.heap)
            edge = int(np.argmax(tracked.deviation))
            index = int(tracked.farthest[edge])
            n = tracked.ids.size
            new_id = state.new_point_id()
            cell = int(tracked.contour[index])
            changes.split_after.append(int(tracked.ids[edge]))
            changes.split_points.append((cell % width, cell // width, new_id))
            cut = edge + 1
            tracked.ids = np.concatenate((tracked.ids[:cut], [new_id], tracked.ids[cut:]))
            tracked.anchors = np.concatenate(
                (tracked.anchors[:cut], [index], tracked.anchors[cut:])
            )
            start = int(tracked.anchors[edge])
            end = int(tracked.anchors[(edge + 2) % (n + 1)])
            left = edge_deviation(tracked.contour, width, start, index)
            right = edge_deviation(tracked.contour, width, index, end)
            tracked.deviation = np.concatenate(
                [tracked.deviation[:edge], [left[0], right[0]], tracked.deviation[edge + 1 :]]
            )
            tracked.farthest = np.concatenate(
                [tracked.farthest[:edge], [left[1], right[1]], tracked.farthest[edge + 1 :]]
            )
            state.version += 1
            tracked.version = state.version
            self._push(state, pid, tracked)
            state.budget -= 1.0
        if len(state.heap) > 4 * len(state.tracked) + 64:
            state.heap = [
                entry
                for entry in state.heap
                if entry[1] in state.tracked and state.tracked[entry[1]].version == entry[2]
            ]
            heapq.heapify(state.heap)

    # ------------------------------------------------------------------ receiver
    def on_receive(self, robot: int, belief: BeliefGrid, message: Message) -> int:
        """Apply one package; see :meth:`on_receive_all`."""
        return self.on_receive_all(robot, belief, [message])

    def on_receive_all(self, robot: int, belief: BeliefGrid, messages: list[Message]) -> int:
        """Apply the packages ``robot`` got this tick and repaint its belief.

        Packages are applied per sender in sequence-number order (see the module
        docstring for gaps and resyncs). Returns the number of belief cells whose
        value changed; cells ``robot`` observed itself are never written.
        """
        state = self._state(robot)
        if any(m.type == RESYNC_REQUEST for m in messages):
            state.resync_requested = True  # answered by a full resync at the next tick
        ours = [m for m in messages if m.type in MAP_PACKAGE_TYPES and m.sender != robot]
        # Increments are applied in runs (one per sender and tick, as a rule), so
        # that receivers of the same runs share the result (polygon_inbound).
        pending: dict[int, list[tuple[int, Payload]]] = {}
        for message in sorted(ours, key=lambda m: (m.sender, m.payload.seq)):
            inbound = state.inbound.get(message.sender)
            if inbound is None:
                inbound = state.inbound[message.sender] = _Inbound(self._maps.empty(message.sender))
            payload = message.payload
            seq = int(payload.seq)
            if seq <= inbound.last_seq:
                continue
            if isinstance(payload, Resync):
                self._apply(inbound, pending.pop(message.sender, []))
                inbound.version, changed = self._maps.resync(inbound.version, seq, payload)
                inbound.dirty = union(inbound.dirty, changed)
                inbound.in_sync = True
            elif inbound.in_sync and seq == inbound.last_seq + 1:
                pending.setdefault(message.sender, []).append((seq, payload))
            else:
                self.gaps_detected += int(inbound.in_sync)
                if inbound.in_sync or inbound.ignored_since_request >= REQUEST_AGAIN_AFTER:
                    inbound.ignored_since_request = 0
                    self.outbox.append(
                        Message(
                            RESYNC_REQUEST,
                            robot,
                            message.sender,
                            HEADER_BYTES + SEQ_BYTES,
                            seq,
                        )
                    )
                inbound.ignored_since_request += 1
                inbound.in_sync = False
            inbound.last_seq = seq
        for sender, packages in pending.items():
            self._apply(state.inbound[sender], packages)
        boxes = [inbound.dirty for inbound in state.inbound.values() if inbound.dirty is not None]
        if not boxes:
            return 0
        for inbound in state.inbound.values():
            inbound.dirty = None
        return self._paint(state, belief, boxes)

    def _apply(self, inbound: _Inbound, packages: list[tuple[int, Payload]]) -> None:
        if packages:
            inbound.version, changed = self._maps.advance(inbound.version, packages)
            inbound.dirty = union(inbound.dirty, changed)

    def _paint(self, state: _RobotState, belief: BeliefGrid, boxes: list[Box]) -> int:
        """Compose the received rasters inside ``boxes`` into ``belief``.

        Outside the boxes no sender's raster changed, and the belief already holds
        the composition there (every change of it was painted when it happened),
        so each box is painted on its own rather than the box holding them all,
        which for senders spread over the map is most of the map. A cell in two
        boxes is written at most once: the second pass finds it up to date.
        """
        height, width = self.shape
        slots = np.empty(len(state.inbound), dtype=np.int64)
        for i, inbound in enumerate(state.inbound.values()):
            self._maps.refresh(inbound.version)
            slots[i] = inbound.version.slot
        n_changed = 0
        for box in boxes:
            x0, y0 = max(box[0], 0), max(box[1], 0)
            x1, y1 = min(box[2], width - 1), min(box[3], height - 1)
            if x0 <= x1 and y0 <= y1:
                n_changed += paint_box(
                    self._maps.rasters,
                    slots,
                    state.own,
                    belief,
                    (y0, y1, x0, x1),
                    FREE,
                    OCCUPIED,
                    UNKNOWN,
                )
        return n_changed

    # ------------------------------------------------------------------ inspection
    def polygons(self, robot: int) -> list[PolygonRecord]:
        """``robot``'s own current approximation (what a full resync would carry), by id."""
        state = self._state(robot)
        width = self.shape[1]
        return [t.record(pid, width) for pid, t in sorted(state.tracked.items())]

    def received(self, robot: int, sender: int) -> list[PolygonRecord]:
        """``sender``'s polygons as ``robot`` rebuilt them from packages, by id."""
        inbound = self._state(robot).inbound.get(sender)
        if inbound is None:
            return []
        return [
            PolygonRecord(pid, p.layer, np.column_stack([p.xy, p.ids]).astype(np.int64))
            for pid, p in sorted(inbound.map.polygons.items())
        ]

    def in_sync(self, robot: int, sender: int) -> bool:
        """Whether ``robot`` applies ``sender``'s increments (no gap since the last resync)."""
        inbound = self._state(robot).inbound.get(sender)
        return inbound is None or inbound.in_sync

    def own_map(self, robot: int) -> BeliefGrid:
        """A copy of the cells ``robot`` observed itself (``UNKNOWN`` elsewhere)."""
        return self._state(robot).own.copy()

    def polygon_map(self, robot: int) -> BeliefGrid:
        """``robot``'s own polygons rasterised over the whole grid (occupied > free > unknown)."""
        height, width = self.shape
        return self._polygon_window(self._state(robot), (0, height - 1, 0, width - 1))

    def _polygon_window(self, state: _RobotState, window: tuple[int, int, int, int]) -> BeliefGrid:
        """The window ``(row_min, row_max, col_min, col_max)`` of the robot's polygon map."""
        row0, row1, col0, col1 = window
        free = np.zeros((row1 - row0 + 1, col1 - col0 + 1), dtype=bool)
        occupied = np.zeros_like(free)
        width = self.shape[1]
        for layer, out in ((OBSERVED_LAYER, free), (OBSTACLE_LAYER, occupied)):
            selected = [t.xy(width) for t in state.tracked.values() if t.layer == layer]
            rasterise_into(selected, row0, col0, out)
        return _compose(free, occupied)

    def approximation_error(self, robot: int) -> float:
        """Share of ``robot``'s own observed cells that its polygon map gets wrong.

        A cell is wrong when the rasterised polygons (occupied over free over
        unknown) disagree with the state the robot observed. 0.0 when the robot
        observed nothing. This is the paper's approximation error (§5.4, Table 2)
        measured against the robot's own map.
        """
        state = self._state(robot)
        # Every observed cell lies in the observed layer's extent.
        row0, row1, col0, col1 = state.extent[OBSERVED_LAYER]
        if row1 < row0:
            return 0.0
        own = state.own[row0 : row1 + 1, col0 : col1 + 1]
        observed = own != UNKNOWN
        n_observed = int(np.count_nonzero(observed))
        if n_observed == 0:
            return 0.0
        wrong = observed & (self._polygon_window(state, (row0, row1, col0, col1)) != own)
        return int(np.count_nonzero(wrong)) / n_observed

    def approximation_errors(self) -> list[float]:
        """:meth:`approximation_error` of every robot, by id."""
        return [self.approximation_error(robot) for robot in range(len(self._robots))]

    def metrics(self) -> dict[str, Any]:
        """For ``result.json``: final approximation errors, vertex counts, resyncs, gaps.

        ``polygon_approximation_error``: per robot, :meth:`approximation_error`
        at the end of the run; ``polygon_approximation_error_mean``: per robot,
        its mean over the run (sampled by :meth:`on_tick` every
        :data:`ERROR_SAMPLE_EVERY` ticks once the robot has observed something,
        after that tick's refinement; ``None`` without a sample), the paper's
        "average approximation error" (§5.4, Table 2); ``polygon_vertices``: per
        robot, vertices of its approximation; ``polygon_resyncs``: full resyncs sent by the team;
        ``polygon_gaps``: times a receiver found a gap in a sender's sequence.
        """
        return {
            "polygon_approximation_error": self.approximation_errors(),
            "polygon_approximation_error_mean": [
                float(np.mean(state.error_samples)) if state.error_samples else None
                for state in self._robots
            ],
            "polygon_vertices": [
                int(sum(t.ids.size for t in state.tracked.values())) for state in self._robots
            ],
            "polygon_resyncs": self.resyncs_sent,
            "polygon_gaps": self.gaps_detected,
        }


def _same_cycle(sources: IntArray, positions: IntArray) -> bool:
    """Whether vertices from old polygons (``sources``, at ``positions`` there) keep their order.

    True when they all come from one old polygon and, read cyclically, their
    positions in it only increase (at most one wrap-around): the new polygon is
    then the old one with some vertices removed, and needs no ``B``.
    """
    if sources.size == 0 or (sources != sources[0]).any():
        return False
    descents = np.count_nonzero(np.diff(positions) < 0) + int(positions[0] < positions[-1])
    return bool(positions.size <= 2 or descents <= 1)


def _runs(ids: IntArray, sources: IntArray, positions: IntArray, lengths: IntArray) -> IntArray:
    """``(first, last)`` id pairs covering ``ids`` by runs of consecutive old vertices.

    Vertex ``i`` continues the run of vertex ``i - 1`` when both come from the
    same old polygon (``sources``, ``-1`` for a new point) and it directly
    follows there (``positions`` in that polygon of ``lengths[source]`` vertices,
    cyclically).
    """
    m = ids.size
    previous = np.roll(np.arange(m), 1)
    known = sources >= 0
    length = lengths[np.where(known, sources, 0)]
    follows = (
        known
        & (sources[previous] == sources)
        & (positions == (positions[previous] + 1) % np.maximum(length, 1))
    )
    if m == 1 or follows.all():
        return np.array([[ids[0], ids[-1]]], dtype=np.int64)
    starts = np.flatnonzero(~follows)
    ends = np.append(starts[1:], starts[0] + m) - 1
    return np.column_stack([ids[starts], ids[ends % m]]).astype(np.int64)


def _compose(free: npt.NDArray[np.bool_], occupied: npt.NDArray[np.bool_]) -> BeliefGrid:
    """Occupied over free over unknown."""
    composite = np.full(free.shape, UNKNOWN, dtype=np.int8)
    composite[free] = FREE
    composite[occupied] = OCCUPIED
    return composite
