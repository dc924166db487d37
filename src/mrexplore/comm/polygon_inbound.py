"""Receivers' copies of the senders' polygon maps, shared between receivers, with rasters.

What a receiver holds from a sender (a :class:`~mrexplore.comm.polygon_packages.PolygonMap`)
depends only on the packages it applied: the last full resync (or none) and the
increments after it, which a receiver applies in sequence order and without gaps
(:mod:`mrexplore.comm.polygon`). So a copy is named by ``(sender, base, applied)``:
``base`` the sequence number of that resync (0: from the start), ``applied`` the last
sequence number applied. Receivers that applied the same packages hold the same
map; under broadcast every receiver of a sender does, and replaying each package
once per receiver, then rasterising each copy again, was most of the mechanism's
time. Here one :class:`MapVersion` per name is kept and shared:

* a receiver moving on to a name some other receiver already reached takes that
  version (and the box of cells the step changed, recorded with it);
* otherwise it applies the package itself: to its own version when no one else
  holds it, else to a copy (copy on write).

Every version keeps the rasters of its two layers over the whole grid (per layer
the even-odd fill plus edges of :func:`~mrexplore.comm.polygon_kernels.rasterise`),
in a slot of one array for all versions (:attr:`SharedMaps.rasters`), brought up
to date lazily: applying packages only widens :attr:`MapVersion.stale`, and
:meth:`SharedMaps.refresh` rasterises that box again before the rasters are read.
A window of a whole-grid raster is the raster of the window (rows are filled from
the crossings of every edge, polygons outside the window add an even number of
crossings left of it or none), so a receiver composes its belief from these
rasters exactly as it would from rasterising the window itself.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from mrexplore.comm.polygon_kernels import rasterise
from mrexplore.comm.polygon_packages import (
    OBSERVED_LAYER,
    OBSTACLE_LAYER,
    Payload,
    PolygonMap,
    Resync,
)

Box = tuple[int, int, int, int]
"""Cells ``(x_min, y_min, x_max, y_max)``, inclusive."""
Name = tuple[int, int, int]
"""``(sender, base, applied)``: which packages a copy of a sender's map is made of."""


def union(a: Box | None, b: Box | None) -> Box | None:
    """The smallest box holding ``a`` and ``b`` (``None`` = empty)."""
    if a is None:
        return b
    if b is None:
        return a
    return min(a[0], b[0]), min(a[1], b[1]), max(a[2], b[2]), max(a[3], b[3])


STEPS_KEPT = 64
"""Boxes of the last this many packages a version remembers (see :attr:`MapVersion.steps`)."""


@dataclass(eq=False)
class MapVersion:
    """One sender's map after the packages named by :attr:`name`, and its rasters.

    Attributes:
        name: ``(sender, base, applied)``, see the module docstring.
        map: the polygons.
        slot: where its rasters are in :attr:`SharedMaps.rasters`: ``[slot, 0]``
            the observed layer, ``[slot, 1]`` the obstacle layer; valid outside
            :attr:`stale`.
        stale: box where the rasters lag behind :attr:`map` (``None``: up to date).
        steps: for the last packages that led here, by sequence number, the box of
            cells the package changed (``None``: none), which is how a receiver
            that held an earlier version learns what changed. For a resync, the
            box of its polygons (what it replaced is the receiver's business).
        holders: receivers holding this version.
    """

    name: Name
    map: PolygonMap
    slot: int
    stale: Box | None = None
    steps: dict[int, Box | None] = field(default_factory=dict)
    holders: int = 0


class SharedMaps:
    """Every receiver's copy of every sender's map, one :class:`MapVersion` per name."""

    def __init__(self, shape: tuple[int, int]) -> None:
        self.shape = shape
        self.versions: dict[Name, MapVersion] = {}
        self.rasters = np.zeros((0, 2, *shape), dtype=bool)
        """Every version's rasters, by slot (one compiled pass reads them all)."""
        self._free_slots: list[int] = []

    def _slot(self) -> int:
        """A free slot of :attr:`rasters` (contents undefined)."""
        if not self._free_slots:
            n = self.rasters.shape[0]
            grown = np.zeros((max(2 * n, 8), 2, *self.shape), dtype=bool)
            grown[:n] = self.rasters
            self.rasters = grown
            self._free_slots = list(range(grown.shape[0] - 1, n - 1, -1))
        return self._free_slots.pop()

    def _new(self, name: Name, polygon_map: PolygonMap) -> MapVersion:
        slot = self._slot()
        self.rasters[slot] = False
        version = MapVersion(name, polygon_map, slot)
        self.versions[name] = version
        return version

    def empty(self, sender: int) -> MapVersion:
        """The map of ``sender`` before any package (taken by the caller)."""
        version = self.versions.get((sender, 0, 0)) or self._new((sender, 0, 0), PolygonMap())
        version.holders += 1
        return version

    def release(self, version: MapVersion) -> None:
        version.holders -= 1
        if version.holders == 0:
            if self.versions.get(version.name) is version:
                del self.versions[version.name]
            self._free_slots.append(version.slot)

    def resync(
        self, version: MapVersion, seq: int, payload: Resync
    ) -> tuple[MapVersion, Box | None]:
        """Apply the full resync ``seq`` to a receiver's ``version``.

        The caller gives up ``version`` and holds the returned one. Returns it and
        the box of cells whose raster the package changed (``None``: none).
        """
        # A resync replaces everything held: the old polygons' cells change too.
        replaced = _polygons_box(version.map)
        name = (version.name[0], seq, seq)
        target = self.versions.get(name)
        if target is None:
            polygon_map = PolygonMap()
            polygon_map.apply(payload)
            target = self._new(name, polygon_map)
            target.stale = polygon_map.take_dirty()
            target.steps[seq] = target.stale
        self.release(version)
        target.holders += 1
        return target, union(replaced, target.steps[seq])

    def advance(
        self, version: MapVersion, packages: list[tuple[int, Payload]]
    ) -> tuple[MapVersion, Box | None]:
        """Apply the increments ``packages`` (``(seq, payload)``, consecutive sequence
        numbers following ``version``'s) to a receiver's ``version``.

        The caller gives up ``version`` and holds the returned one. Returns it and
        the box of cells whose raster the packages changed (``None``: none).
        """
        sender, base, _ = version.name
        name = (sender, base, packages[-1][0])
        target = self.versions.get(name)
        if target is not None and all(seq in target.steps for seq, _ in packages):
            self.release(version)
            target.holders += 1
            box: Box | None = None
            for seq, _ in packages:
                box = union(box, target.steps[seq])
            return target, box
        # (A version of this name reached by other packages lacks our steps; ours
        # replaces it in the store, its holders keep it.)
        if version.holders == 1:
            if self.versions.get(version.name) is version:
                del self.versions[version.name]
            target = version
        else:
            version.holders -= 1
            slot = self._slot()
            self.rasters[slot] = self.rasters[version.slot]
            target = MapVersion(
                version.name,
                version.map.copy(),
                slot,
                version.stale,
                dict(version.steps),
                holders=1,
            )
        target.name = name
        self.versions[name] = target
        box = None
        for seq, payload in packages:
            target.map.apply(payload)
            step = target.map.take_dirty()
            target.steps[seq] = step
            box = union(box, step)
        target.stale = union(target.stale, box)
        if len(target.steps) > STEPS_KEPT:
            oldest = packages[-1][0] - STEPS_KEPT
            target.steps = {seq: b for seq, b in target.steps.items() if seq > oldest}
        return target, box

    def refresh(self, version: MapVersion) -> None:
        """Bring ``version``'s rasters up to date."""
        if version.stale is not None:
            height, width = self.shape
            box = version.stale
            x0, y0 = max(box[0], 0), max(box[1], 0)
            x1, y1 = min(box[2], width - 1), min(box[3], height - 1)
            if x0 <= x1 and y0 <= y1:
                # The polygons that reach into the box, by layer (one pass).
                selected: tuple[list[npt.NDArray[np.int32]], ...] = ([], [])
                for polygon in version.map.polygons.values():
                    b = polygon.bbox
                    if b[0] <= x1 and b[2] >= x0 and b[1] <= y1 and b[3] >= y0:
                        selected[polygon.layer].append(polygon.xy)
                for layer in (OBSERVED_LAYER, OBSTACLE_LAYER):
                    window = self.rasters[version.slot, layer, y0 : y1 + 1, x0 : x1 + 1]
                    window[:] = False
                    rasterise_into(selected[layer], y0, x0, window)
            version.stale = None


def rasterise_into(
    polygons: list[npt.NDArray[np.int32]], row0: int, col0: int, out: npt.NDArray[np.bool_]
) -> None:
    """Even-odd fill plus edges of ``polygons`` (one sender's layer), ORed into ``out``,
    whose cell ``[0, 0]`` is grid cell ``(row0, col0)``."""
    if not polygons:
        return
    offsets = np.zeros(len(polygons) + 1, dtype=np.int64)
    offsets[1:] = np.cumsum(np.fromiter((len(p) for p in polygons), np.int64, len(polygons)))
    rasterise(np.concatenate(polygons), offsets, row0, col0, out)


def _polygons_box(polygon_map: PolygonMap) -> Box | None:
    box: Box | None = None
    for polygon in polygon_map.polygons.values():
        box = union(box, polygon.bbox)
    return box
