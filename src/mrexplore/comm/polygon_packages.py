"""Packages of the polygon map-sharing mechanism: payloads, byte layout, replay.

Meier, Stachniss & Burgard (2005) §3 and §5.3 name the packages; this module
defines what each carries on the wire and how a receiver applies it to its copy
of a sender's polygon map (:class:`PolygonMap`). The sender builds its packages
so that applying them, in sequence-number order, to the map it had before
reproduces the map it has now.

Byte layout (little-endian; every message also carries the 7-byte header of
:mod:`mrexplore.comm.bytes`). A *point* is ``x int32, y int32, id uint32``
(:data:`~mrexplore.comm.bytes.POLYGON_POINT_BYTES` = 12; ``x`` = column, ``y`` =
row of a cell centre). A *polygon record* is ``polygon id uint32, layer uint8,
n_points uint16`` (7 bytes) followed by its points in order.

A *run record* is ``polygon id uint32, layer uint8, n_runs uint16`` (7 bytes)
followed by ``n_runs`` runs ``first id uint32, last id uint32`` (8 bytes): the
polygon is the concatenation of its runs, a run being the vertices from
``first`` to ``last`` walking forward through the polygon that holds ``first``
just before the package (a run of a new point is that point alone).

==========  ==========================================================  ==========================
type        payload                                                     bytes (after header)
==========  ==========================================================  ==========================
``VP``      seq uint32, n uint16, n x point id uint32                   6 + 4 n
``ES``      seq uint32, n uint16, n x (after-id uint32, point)          6 + 16 n
``B``       seq uint32, flags uint8 = 0, k uint16, k x point (new       9 + 12 k + sum(7 + 8 r_i)
            points), n uint16, n x run record
``B`` sync  seq uint32, flags uint8 = 1, n uint16, n x polygon record   7 + sum(7 + 12 m_i)
``EP``      seq uint32, n uint16, n x polygon record                    6 + sum(7 + 12 m_i)
==========  ==========================================================  ==========================

``flags`` bit 0 marks a full resync (:class:`Resync`), else a restructure
(:class:`BrokenBoundary`). The extra field sizes below (``SEQ_BYTES`` ...
``RUN_BYTES``) are the only place they are defined.

``TPT`` (target point transmission) is the paper's fifth package type; it
carries a robot's chosen target and belongs to the coordination strategy, not
to map sharing (see :data:`TPT`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from mrexplore.comm.bytes import (
    COUNT_BYTES,
    FLAGS_BYTES,
    HEADER_BYTES,
    LAYER_BYTES,
    POINT_ID_BYTES,
    POLYGON_ID_BYTES,
    POLYGON_POINT_BYTES,
    SEQ_BYTES,
)
from mrexplore.errors import PolygonLimitError

IntArray = npt.NDArray[np.int64]

# Package types (message ``type`` strings), named as in Meier et al. §5.3.
TPT = "TPT"
"""Target point transmission: a robot's chosen target (sent by a coordination strategy)."""
ES = "ES"
"""Edge split: new vertices inserted into existing edges."""
B = "B"
"""Broken boundary: polygons re-defined from surviving vertices (split, merge), or a resync."""
VP = "VP"
"""Vanished points: vertices removed from the approximation."""
EP = "EP"
"""Emerged points: polygons of newly appeared boundaries."""

PAPER_PACKAGE_TYPES = frozenset({TPT, ES, B, VP, EP})
"""All five package types of the paper's Table 1."""
MAP_PACKAGE_TYPES = frozenset({ES, B, VP, EP})
"""The four that carry the polygon map (what :class:`PolygonSharing` sends)."""

# Field sizes in bytes come from the byte model (mrexplore.comm.bytes).
POLYGON_RECORD_HEADER_BYTES = POLYGON_ID_BYTES + LAYER_BYTES + COUNT_BYTES
"""Bytes of a polygon record (or a run record) before its points (runs): 7."""
RUN_BYTES = 2 * POINT_ID_BYTES
"""A run of known vertices: first id, last id (8)."""
MAX_COUNT = 2 ** (8 * COUNT_BYTES) - 1
"""Largest count a uint16 field holds (65535)."""

FULL_RESYNC = 1
"""``B`` flag bit: discard everything held from this sender first."""

OBSERVED_LAYER = 0
"""Layer of the polygons bounding the area the sender observed (free or occupied)."""
OBSTACLE_LAYER = 1
"""Layer of the polygons bounding the occupied cells the sender observed."""


@dataclass(frozen=True, slots=True)
class PolygonRecord:
    """One polygon on the wire: id, layer and its points in order.

    ``points`` is an ``n x 3`` int64 array of ``(x, y, id)`` rows.
    """

    polygon_id: int
    layer: int
    points: IntArray


@dataclass(frozen=True, slots=True)
class VanishedPoints:
    """``VP`` payload: ids of vertices that left the approximation."""

    seq: int
    point_ids: IntArray


@dataclass(frozen=True, slots=True)
class EdgeSplits:
    """``ES`` payload: ``points[i]`` (x, y, id) goes right after vertex ``after_ids[i]``."""

    seq: int
    after_ids: IntArray
    points: IntArray


@dataclass(frozen=True, slots=True)
class PolygonRuns:
    """One polygon of a ``B`` restructure: id, layer and its runs.

    ``runs`` is an ``n x 2`` int64 array of ``(first id, last id)`` rows; see the
    module docstring.
    """

    polygon_id: int
    layer: int
    runs: IntArray


@dataclass(frozen=True, slots=True)
class BrokenBoundary:
    """``B`` payload (flags 0): polygons re-linked from known vertices.

    ``new_points`` (``n x 3``: x, y, id) are vertices the receiver has not seen
    (closing points of case 3); ``polygons`` replace the polygons of the same
    id, and every vertex they list leaves the polygon that held it.
    """

    seq: int
    new_points: IntArray
    polygons: tuple[PolygonRuns, ...]


@dataclass(frozen=True, slots=True)
class Resync:
    """``B`` payload (flags 1): the sender's whole polygon map; replaces all held from it."""

    seq: int
    polygons: tuple[PolygonRecord, ...]


@dataclass(frozen=True, slots=True)
class EmergedPoints:
    """``EP`` payload: polygons of boundaries that appeared."""

    seq: int
    polygons: tuple[PolygonRecord, ...]


Payload = VanishedPoints | EdgeSplits | BrokenBoundary | Resync | EmergedPoints


def _check_count(n: int, what: str) -> None:
    if n > MAX_COUNT:
        raise PolygonLimitError(
            f"a polygon package would carry {n} {what}; the uint16 count field holds "
            f"{MAX_COUNT} (use a larger epsilon or a smaller map)"
        )


def _records_bytes(item_counts: list[int], item_bytes: int, items: str) -> int:
    """Bytes of polygon (or run) records: per record its header and ``item_counts[i]``
    items of ``item_bytes``; every count must fit its uint16 field."""
    _check_count(len(item_counts), "polygons")
    total = 0
    for n in item_counts:
        _check_count(n, f"{items} in one polygon")
        total += POLYGON_RECORD_HEADER_BYTES + item_bytes * n
    return total


def _polygons_bytes(polygons: tuple[PolygonRecord, ...]) -> int:
    return _records_bytes([int(r.points.shape[0]) for r in polygons], POLYGON_POINT_BYTES, "points")


def vanished_points_size(n_points: int) -> int:
    """Bytes of a ``VP`` message removing ``n_points`` vertices.

    >>> vanished_points_size(3)
    25
    """
    _check_count(n_points, "vanished points")
    return HEADER_BYTES + SEQ_BYTES + COUNT_BYTES + POINT_ID_BYTES * n_points


def edge_splits_size(n_splits: int) -> int:
    """Bytes of an ``ES`` message with ``n_splits`` new vertices.

    >>> edge_splits_size(1)
    29
    """
    _check_count(n_splits, "edge splits")
    return (
        HEADER_BYTES + SEQ_BYTES + COUNT_BYTES + (POINT_ID_BYTES + POLYGON_POINT_BYTES) * n_splits
    )


def broken_boundary_size(n_new_points: int, polygons: tuple[PolygonRuns, ...]) -> int:
    """Bytes of a ``B`` restructure with ``n_new_points`` new points and ``polygons``.

    >>> import numpy as np
    >>> broken_boundary_size(1, (PolygonRuns(1, 0, np.zeros((2, 2), dtype=np.int64)),))
    51
    """
    _check_count(n_new_points, "new points")
    runs = _records_bytes([int(r.runs.shape[0]) for r in polygons], RUN_BYTES, "runs")
    return (
        HEADER_BYTES
        + SEQ_BYTES
        + FLAGS_BYTES
        + COUNT_BYTES
        + POLYGON_POINT_BYTES * n_new_points
        + COUNT_BYTES
        + runs
    )


def resync_size(polygons: tuple[PolygonRecord, ...]) -> int:
    """Bytes of a ``B`` full resync carrying ``polygons``.

    >>> import numpy as np
    >>> resync_size((PolygonRecord(1, 0, np.zeros((2, 3), dtype=np.int64)),))
    45
    """
    return HEADER_BYTES + SEQ_BYTES + FLAGS_BYTES + COUNT_BYTES + _polygons_bytes(polygons)


def emerged_points_size(polygons: tuple[PolygonRecord, ...]) -> int:
    """Bytes of an ``EP`` message carrying ``polygons``.

    >>> import numpy as np
    >>> emerged_points_size((PolygonRecord(1, 1, np.zeros((1, 3), dtype=np.int64)),))
    32
    """
    return HEADER_BYTES + SEQ_BYTES + COUNT_BYTES + _polygons_bytes(polygons)


def payload_size(package_type: str, payload: Payload) -> int:
    """Bytes on the wire of a package of ``package_type`` with ``payload``."""
    if package_type == VP:
        assert isinstance(payload, VanishedPoints)
        return vanished_points_size(int(payload.point_ids.size))
    if package_type == ES:
        assert isinstance(payload, EdgeSplits)
        return edge_splits_size(int(payload.after_ids.size))
    if package_type == B and isinstance(payload, BrokenBoundary):
        return broken_boundary_size(int(payload.new_points.shape[0]), payload.polygons)
    if package_type == B:
        assert isinstance(payload, Resync)
        return resync_size(payload.polygons)
    if package_type == EP:
        assert isinstance(payload, EmergedPoints)
        return emerged_points_size(payload.polygons)
    raise ValueError(f"not a polygon map package type: {package_type!r}")


@dataclass
class Polygon:
    """A polygon as a receiver holds it.

    Attributes:
        layer: :data:`OBSERVED_LAYER` or :data:`OBSTACLE_LAYER`.
        ids: vertex ids in order (int64).
        xy: ``n x 2`` int32 cell centres ``(x, y) = (col, row)``, aligned with ``ids``.
        bbox: ``(x_min, y_min, x_max, y_max)`` covering every vertex the polygon
            has had since it was last defined in full (never shrinks until then).
    """

    layer: int
    ids: IntArray
    xy: npt.NDArray[np.int32]
    bbox: tuple[int, int, int, int] = field(default=(0, 0, -1, -1))

    def __post_init__(self) -> None:
        if self.ids.size and self.bbox[2] < self.bbox[0]:
            self.bbox = _bbox_of(self.xy)


def _bbox_of(xy: npt.NDArray[np.int32]) -> tuple[int, int, int, int]:
    lo = xy.min(axis=0)
    hi = xy.max(axis=0)
    return int(lo[0]), int(lo[1]), int(hi[0]), int(hi[1])


def _union(
    a: tuple[int, int, int, int] | None, b: tuple[int, int, int, int]
) -> tuple[int, int, int, int]:
    if a is None:
        return b
    return min(a[0], b[0]), min(a[1], b[1]), max(a[2], b[2]), max(a[3], b[3])


def _edge_keys(xy: npt.NDArray[np.int32]) -> IntArray:
    """One int64 per directed edge ``xy[i] -> xy[i + 1]`` (cyclic; a single vertex is
    the edge from it to itself), 16 bits per coordinate."""
    xy = xy.astype(np.int64)
    following = np.roll(xy, -1, axis=0)
    return xy[:, 0] | (xy[:, 1] << 16) | (following[:, 0] << 32) | (following[:, 1] << 48)


def changed_edges_box(
    old: npt.NDArray[np.int32], new: npt.NDArray[np.int32]
) -> tuple[int, int, int, int] | None:
    """Box of the cells whose raster can differ when polygon ``old`` becomes ``new``.

    ``rasterise`` draws every directed edge (vertex ``i`` to vertex ``i + 1``) and
    fills each row from the crossings of all edges. Edges in both polygons (as a
    multiset of directed edges) draw and cross the same; the others, removed or
    added, change the drawn cells along themselves and the crossings of the rows
    they cross, between their ends. Both polygons are closed, so each row gains
    and loses an even number of crossings in all, and the parity of the crossings
    left of a cell changes only between the changed crossings. Hence a box
    holding every changed edge (``None``: no edge changed) holds every change.
    Coordinates must lie in ``[0, 2**15)``; otherwise both polygons' boxes.
    """
    if min(int(old.min()), int(new.min())) < 0 or max(int(old.max()), int(new.max())) >= 2**15:
        return _union(_bbox_of(old), _bbox_of(new))
    keys_old, counts_old = np.unique(_edge_keys(old), return_counts=True)
    keys_new, counts_new = np.unique(_edge_keys(new), return_counts=True)
    keys = np.union1d(keys_old, keys_new)
    count_old = np.zeros(keys.size, dtype=np.int64)
    count_new = np.zeros(keys.size, dtype=np.int64)
    count_old[np.searchsorted(keys, keys_old)] = counts_old
    count_new[np.searchsorted(keys, keys_new)] = counts_new
    changed = keys[count_old != count_new]
    if changed.size == 0:
        return None
    mask = (1 << 16) - 1
    xs = np.concatenate([changed & mask, (changed >> 32) & mask])
    ys = np.concatenate([(changed >> 16) & mask, (changed >> 48) & mask])
    return int(xs.min()), int(ys.min()), int(xs.max()), int(ys.max())


class PolygonMap:
    """One sender's polygon map as rebuilt from its packages.

    Applying a package also records, in :attr:`dirty`, a box of cells
    ``(x_min, y_min, x_max, y_max)`` outside of which the rasterised map did not
    change (``None`` = nothing changed since :meth:`take_dirty`).

    A changed polygon is replaced by a new :class:`Polygon`, never modified, so
    :meth:`copy` can share the polygons with the copy.
    """

    def __init__(self) -> None:
        self.polygons: dict[int, Polygon] = {}
        self.owner: dict[int, int] = {}
        self.dirty: tuple[int, int, int, int] | None = None

    def copy(self) -> PolygonMap:
        """A map with the same polygons that packages can be applied to separately."""
        copy = PolygonMap()
        copy.polygons = dict(self.polygons)
        copy.owner = dict(self.owner)
        copy.dirty = self.dirty
        return copy

    def take_dirty(self) -> tuple[int, int, int, int] | None:
        """The dirty box, which is reset."""
        box, self.dirty = self.dirty, None
        return box

    def _mark(self, box: tuple[int, int, int, int]) -> None:
        self.dirty = _union(self.dirty, box)

    def _neighbourhood(self, polygon: Polygon, position: int) -> tuple[int, int, int, int]:
        """Box of the vertex at ``position`` and its two neighbours."""
        n = polygon.ids.size
        (xa, ya), (xb, yb), (xc, yc) = polygon.xy[
            [(position - 1) % n, position, (position + 1) % n]
        ].tolist()
        return min(xa, xb, xc), min(ya, yb, yc), max(xa, xb, xc), max(ya, yb, yc)

    def _remove(self, point_id: int) -> None:
        polygon_id = self.owner.pop(point_id, None)
        if polygon_id is None:
            return
        polygon = self.polygons[polygon_id]
        position = int(np.flatnonzero(polygon.ids == point_id)[0])
        self._mark(self._neighbourhood(polygon, position))
        if polygon.ids.size == 1:
            del self.polygons[polygon_id]
            return
        self.polygons[polygon_id] = Polygon(
            polygon.layer,
            np.concatenate((polygon.ids[:position], polygon.ids[position + 1 :])),
            np.concatenate((polygon.xy[:position], polygon.xy[position + 1 :])),
            polygon.bbox,
        )

    def _define(self, record: PolygonRecord) -> None:
        old = self.polygons.pop(record.polygon_id, None)
        if old is not None:
            for point_id in old.ids.tolist():
                self.owner.pop(point_id, None)
        points = record.points
        if points.shape[0] == 0:
            if old is not None:
                self._mark(old.bbox)
            return
        ids = points[:, 2].astype(np.int64)
        for point_id in ids.tolist():
            if point_id in self.owner:
                self._remove(point_id)
        polygon = Polygon(record.layer, ids, points[:, :2].astype(np.int32))
        self.polygons[record.polygon_id] = polygon
        for point_id in ids.tolist():
            self.owner[point_id] = record.polygon_id
        if old is None:
            self._mark(polygon.bbox)
        elif old.layer != polygon.layer:
            self._mark(old.bbox)
            self._mark(polygon.bbox)
        else:
            changed = changed_edges_box(old.xy, polygon.xy)
            if changed is not None:
                self._mark(changed)

    def apply(self, payload: Payload) -> None:
        """Apply one package (the caller checks sequence numbers)."""
        if isinstance(payload, VanishedPoints):
            for point_id in payload.point_ids.tolist():
                self._remove(point_id)
        elif isinstance(payload, EdgeSplits):
            for after, point in zip(payload.after_ids.tolist(), payload.points, strict=True):
                self._insert(after, point)
        elif isinstance(payload, Resync):
            for polygon in self.polygons.values():
                self._mark(polygon.bbox)
            self.polygons.clear()
            self.owner.clear()
            for record in payload.polygons:
                self._define(record)
        elif isinstance(payload, BrokenBoundary):
            # Expand every run against the polygons as they are before the package.
            new = {int(p[2]): p for p in payload.new_points}
            records = [
                PolygonRecord(r.polygon_id, r.layer, self._expand(r.runs, new))
                for r in payload.polygons
            ]
            for record in records:
                self._define(record)
        else:
            for record in payload.polygons:
                self._define(record)

    def _expand(self, runs: IntArray, new: dict[int, IntArray]) -> IntArray:
        """``(x, y, id)`` rows of the vertices the runs stand for."""
        parts: list[IntArray] = []
        for first, last in runs.tolist():
            if first in new:
                parts.append(new[first].reshape(1, 3))
                continue
            polygon_id = self.owner.get(first)
            if polygon_id is None:  # cannot happen for a package stream in order
                continue
            polygon = self.polygons[polygon_id]
            start = int(np.flatnonzero(polygon.ids == first)[0])
            found = np.flatnonzero(polygon.ids == last)
            end = int(found[0]) if found.size else start
            positions = np.arange(start, start + (end - start) % polygon.ids.size + 1)
            positions %= polygon.ids.size
            parts.append(
                np.column_stack([polygon.xy[positions], polygon.ids[positions]]).astype(np.int64)
            )
        if not parts:
            return np.zeros((0, 3), dtype=np.int64)
        return np.concatenate(parts)

    def _insert(self, after: int, point: IntArray) -> None:
        polygon_id = self.owner.get(after)
        if polygon_id is None:  # cannot happen for a package stream in order
            return
        polygon = self.polygons[polygon_id]
        position = int(np.flatnonzero(polygon.ids == after)[0]) + 1
        x, y, point_id = int(point[0]), int(point[1]), int(point[2])
        ids, xy, b = polygon.ids, polygon.xy, polygon.bbox
        polygon = Polygon(
            polygon.layer,
            np.concatenate((ids[:position], np.array([point_id]), ids[position:])),
            np.concatenate((xy[:position], np.array([[x, y]], dtype=np.int32), xy[position:])),
            (min(b[0], x), min(b[1], y), max(b[2], x), max(b[3], y)),
        )
        self.polygons[polygon_id] = polygon
        self.owner[point_id] = polygon_id
        self._mark(self._neighbourhood(polygon, position))

    def records(self) -> list[tuple[int, int, IntArray]]:
        """``(polygon id, layer, ids)`` of every polygon, sorted by id (for comparisons)."""
        return [(pid, p.layer, p.ids.copy()) for pid, p in sorted(self.polygons.items())]
