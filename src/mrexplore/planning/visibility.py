"""Line of sight on a grid: the one definition used by sensing, planning and validation.

A cell ``t`` is *visible* from a cell ``s`` when the grid line from ``s`` to ``t``
(:func:`bresenham_line`) crosses no obstacle:

1. every cell strictly between ``s`` and ``t`` on the line is free, and
2. no diagonal step of the line (the last step into ``t`` included) squeezes
   between two occupied cells, i.e. for a step from ``(r, c)`` to
   ``(r + dr, c + dc)`` with ``dr, dc != 0``, the cells ``(r + dr, c)`` and
   ``(r, c + dc)`` are not both occupied.

``t`` itself may be occupied: the obstacle that blocks a ray is seen. ``s`` is
always visible from itself. Both ``s`` and ``t`` must lie in the grid; every cell
the rule looks at then lies in the rectangle spanned by ``s`` and ``t``, hence in
the grid too.

The line (a Bresenham variant, fixed here once and for all): with
``n = max(|dr|, |dc|)`` steps along the major axis and ``m`` the absolute offset
along the minor axis, the cell at major step ``i`` (``0 <= i <= n``) has minor
offset ``floor(i * m / n + 1/2)`` -- the cell nearest the ideal line, exact ties
rounded away from ``s`` -- computed in integers as ``(2 * i * m + n) // (2 * n)``.
Signs are applied afterwards, so the line to ``(-dr, dc)`` is the mirror image of
the line to ``(dr, dc)``. When ``|dr| == |dc|`` the line is the pure diagonal.
Lines are not reversible in general: ``t`` may see ``s`` when ``s`` cannot see
``t``, and vice versa.

For speed, :func:`ray_table` merges the lines to every cell of a disk into a
prefix tree (lines that start with the same cells share nodes), stored in
depth-first order with skip pointers, so one linear pass
(:func:`visible_cells_kernel`) tests each shared prefix once and jumps over every
line behind a blocking cell. At radius 50 the tree has about 55,000 nodes for
7,845 cells.

Units: offsets, positions and radii are in cells.
"""

from __future__ import annotations

import functools
import hashlib
import itertools
import logging
import math
import os
from dataclasses import dataclass
from pathlib import Path

import numba
import numpy as np
import numpy.typing as npt

from mrexplore.planning._validate import as_radius

logger = logging.getLogger(__name__)

__all__ = [
    "RayTable",
    "bresenham_line",
    "clip_radius",
    "disk_offsets",
    "in_sight_kernel",
    "is_visible_kernel",
    "ray_table",
    "visible_cells_kernel",
]

#: Bits of :attr:`RayTable.flags`.
FLAG_TARGET = 1  # a line ends at this node: its cell is visible when reached
FLAG_DIAGONAL = 2  # the step into this node's cell is diagonal (squeeze check)


def _line_minor(i: int, n: int, m: int) -> int:
    """Minor-axis offset (cells, >= 0) at major step ``i`` of a line of ``n`` steps rising ``m``.

    The single definition of the line; :func:`is_visible_kernel` runs a compiled
    copy of this very function.
    """
    return (2 * i * m + n) // (2 * n)


_line_minor_compiled = numba.njit(cache=True, inline="always")(_line_minor)


def bresenham_line(start: tuple[int, int], end: tuple[int, int]) -> npt.NDArray[np.int64]:
    """Cells of the grid line from ``start`` to ``end`` inclusive, as ``(K, 2)`` ``(row, col)``.

    See the module docstring for the exact rounding rule.

    Example:
        >>> bresenham_line((0, 0), (1, 3)).tolist()
        [[0, 0], [0, 1], [1, 2], [1, 3]]
    """
    r0, c0 = int(start[0]), int(start[1])
    dr, dc = int(end[0]) - r0, int(end[1]) - c0
    n = max(abs(dr), abs(dc))
    cells = np.empty((n + 1, 2), dtype=np.int64)
    cells[0] = (r0, c0)
    sr = 1 if dr >= 0 else -1
    sc = 1 if dc >= 0 else -1
    for i in range(1, n + 1):
        if abs(dr) >= abs(dc):
            cells[i] = (r0 + sr * i, c0 + sc * _line_minor(i, n, abs(dc)))
        else:
            cells[i] = (r0 + sr * _line_minor(i, n, abs(dr)), c0 + sc * i)
    return cells


@functools.lru_cache(maxsize=64)
def _disk_offsets_cached(radius: float) -> npt.NDArray[np.int64]:
    reach = math.floor(radius)
    span = np.arange(-reach, reach + 1, dtype=np.int64)
    d_row, d_col = np.meshgrid(span, span, indexing="ij")
    inside = d_row * d_row + d_col * d_col <= radius * radius
    offsets = np.stack([d_row[inside], d_col[inside]], axis=1)
    offsets.setflags(write=False)
    return offsets


def disk_offsets(radius: float) -> npt.NDArray[np.int64]:
    """Offsets ``(dr, dc)`` with ``dr**2 + dc**2 <= radius**2``, in raster order.

    Args:
        radius: disk radius in cells, finite and ``>= 0``.

    Returns:
        Read-only ``(K, 2)`` int64 array, cached per radius; ``(0, 0)`` is included.

    Example:
        >>> disk_offsets(1.0).tolist()
        [[-1, 0], [0, -1], [0, 0], [0, 1], [1, 0]]
    """
    return _disk_offsets_cached(as_radius(radius))


def clip_radius(radius: float, shape: tuple[int, ...]) -> float:
    """``radius`` (cells), capped so that its disk still covers the whole grid of ``shape``.

    Any larger disk holds the same grid cells, so results do not change; only the
    size of the tables built for it does.
    """
    cover = math.sqrt((shape[0] - 1) ** 2 + (shape[1] - 1) ** 2) + 1.0
    return min(radius, float(math.ceil(cover)))


@dataclass(frozen=True, eq=False)
class RayTable:
    """The lines from a viewer to every cell of a disk, merged into a prefix tree.

    Node ``i`` stands for one cell of one or more lines, at offset
    ``cell[i]`` from the viewer, entered from the previous line cell
    ``parent[i]``; all lines through node ``i`` share their cells up to it. Nodes
    are stored depth first, so node ``i``'s descendants are ``i + 1 .. skip[i] - 1``.
    Walking node ``i`` means, in order:

    1. if the step ``parent -> cell`` is diagonal and squeezes between two
       occupied cells, skip the subtree;
    2. if the node ends a line (``FLAG_TARGET``), its cell is visible;
    3. if the cell is occupied, skip the subtree (it blocks every longer line).

    The viewer's own cell is not in the table (it is always visible).

    Attributes:
        radius: disk radius, cells.
        flags: ``(N,)`` uint8, bit ``FLAG_TARGET`` and bit ``FLAG_DIAGONAL``.
        cell: ``(N, 2)`` int32 offsets ``(dr, dc)`` of the node's cell.
        parent: ``(N, 2)`` int32 offsets of the previous cell on its lines.
        skip: ``(N,)`` int32 index of the first node after ``i``'s subtree.
        n_cells: number of cells in the disk, the viewer's included.
        reach: largest ``|dr|`` or ``|dc|`` in the table (``floor(radius)``).
    """

    radius: float
    flags: npt.NDArray[np.uint8]
    cell: npt.NDArray[np.int32]
    parent: npt.NDArray[np.int32]
    skip: npt.NDArray[np.int32]
    n_cells: int
    reach: int


_TABLE_ARRAYS = ("flags", "cell", "parent", "skip")


def _table_cache_file(radius: float) -> Path | None:
    """Where the table of ``radius`` is cached on disk: next to numba's cache (this
    package's ``__pycache__``, or ``$MREXPLORE_CACHE_DIR``), under a name that holds a
    hash of this module's source, so that any change to the line rule invalidates it."""
    try:
        source = Path(__file__).read_bytes()
    except OSError:
        return None
    digest = hashlib.sha256(source).hexdigest()[:16]
    folder = Path(os.environ.get("MREXPLORE_CACHE_DIR") or Path(__file__).parent / "__pycache__")
    return folder / f"raytable-{radius!r}-{digest}.npz"


@functools.lru_cache(maxsize=16)
def _ray_table_cached(radius: float) -> RayTable:
    """The table of ``radius``: from the disk cache if there, else built (and cached).

    Building is pure Python (about 1 s at radius 40); a sweep's worker processes
    would each pay it, so the table is kept on disk like the compiled kernels.
    """
    path = _table_cache_file(radius)
    if path is not None and path.exists():
        try:
            with np.load(path) as data:
                arrays = {name: np.array(data[name]) for name in _TABLE_ARRAYS}
                n_cells, reach = int(data["n_cells"]), int(data["reach"])
            for array in arrays.values():
                array.setflags(write=False)
            return RayTable(radius=radius, n_cells=n_cells, reach=reach, **arrays)
        except (OSError, KeyError, ValueError) as error:
            logger.debug("ray table cache %s unreadable (%s): rebuilding", path, error)
    table = _build_ray_table(radius)
    if path is not None:
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            temporary = path.with_name(f"{path.name}.{os.getpid()}.tmp.npz")
            np.savez(
                temporary,
                n_cells=table.n_cells,
                reach=table.reach,
                **{name: getattr(table, name) for name in _TABLE_ARRAYS},
            )
            os.replace(temporary, path)  # atomic: concurrent workers never read half a file
        except OSError as error:
            logger.debug("ray table cache %s not written (%s)", path, error)
    return table


def _build_ray_table(radius: float) -> RayTable:
    # Trie keyed by cell offset: a node's children are the next cells of its lines.
    children: list[dict[tuple[int, int], int]] = [{}]  # node 0: the viewer
    cells: list[tuple[int, int]] = [(0, 0)]
    parents: list[tuple[int, int]] = [(0, 0)]
    targets: list[bool] = [True]
    for d_row, d_col in _disk_offsets_cached(radius).tolist():
        node = 0
        line = bresenham_line((0, 0), (d_row, d_col)).tolist()
        for (prev_r, prev_c), (r, c) in itertools.pairwise(line):
            child = children[node].get((r, c))
            if child is None:
                child = len(cells)
                children[node][(r, c)] = child
                children.append({})
                cells.append((r, c))
                parents.append((prev_r, prev_c))
                targets.append(False)
            node = child
        targets[node] = True

    n_nodes = len(cells) - 1  # the viewer is not stored
    flags = np.zeros(n_nodes, dtype=np.uint8)
    cell = np.empty((n_nodes, 2), dtype=np.int32)
    parent = np.empty((n_nodes, 2), dtype=np.int32)
    skip = np.empty(n_nodes, dtype=np.int32)
    # Iterative depth-first numbering; children keep insertion (raster) order.
    position = 0
    stack: list[tuple[int, int]] = [(child, -1) for child in reversed(children[0].values())]
    while stack:
        node, start = stack.pop()
        if start >= 0:
            skip[start] = position
            continue
        (r, c), (prev_r, prev_c) = cells[node], parents[node]
        cell[position] = (r, c)
        parent[position] = (prev_r, prev_c)
        flags[position] = (FLAG_TARGET if targets[node] else 0) | (
            FLAG_DIAGONAL if r != prev_r and c != prev_c else 0
        )
        stack.append((node, position))
        position += 1
        stack.extend((child, -1) for child in reversed(children[node].values()))
    for array in (flags, cell, parent, skip):
        array.setflags(write=False)
    n_cells = int(np.count_nonzero(flags & FLAG_TARGET)) + 1
    return RayTable(
        radius=radius,
        flags=flags,
        cell=cell,
        parent=parent,
        skip=skip,
        n_cells=n_cells,
        reach=math.floor(radius),
    )


def ray_table(radius: float) -> RayTable:
    """The :class:`RayTable` of a disk of ``radius`` cells, built once per radius and cached.

    Building is pure Python, about 1 s at radius 40, once per radius: the table is
    then cached in memory and on disk (see :func:`_table_cache_file`).
    """
    return _ray_table_cached(as_radius(radius))


@numba.njit(cache=True, nogil=True)
def visible_cells_kernel(
    occupied: npt.NDArray[np.bool_],
    height: int,
    width: int,
    row: int,
    col: int,
    flags: npt.NDArray[np.uint8],
    cell: npt.NDArray[np.int32],
    parent: npt.NDArray[np.int32],
    skip: npt.NDArray[np.int32],
    reach: int,
    out: npt.NDArray[np.int64],
) -> int:
    """Write the flat indices of the cells visible from ``(row, col)`` to ``out``.

    Args:
        occupied: flat (row-major) boolean grid of ``height * width`` cells,
            ``True`` where a cell blocks sight.
        height, width: grid shape, cells.
        row, col: viewer cell, inside the grid.
        flags, cell, parent, skip, reach: the fields of a :class:`RayTable`.
        out: room for ``RayTable.n_cells`` flat indices ``row * width + col``.

    Returns:
        How many cells were written: the viewer's cell first, then the others in
        the table's order.
    """
    n_nodes = flags.shape[0]
    base = row * width + col
    out[0] = base
    n_out = 1
    i = 0
    if reach <= row < height - reach and reach <= col < width - reach:
        # The whole disk is inside the grid: no bounds checks.
        while i < n_nodes:
            d_row = cell[i, 0]
            d_col = cell[i, 1]
            index = base + d_row * width + d_col
            node_flags = flags[i]
            if node_flags & FLAG_DIAGONAL:
                # The two cells beside the step (r', c) -> (r, c'): (r, c) and (r', c').
                beside_a = index + parent[i, 1] - d_col
                beside_b = index + (parent[i, 0] - d_row) * width
                if occupied[beside_a] and occupied[beside_b]:
                    i = skip[i]
                    continue
            if node_flags & FLAG_TARGET:
                out[n_out] = index
                n_out += 1
            if occupied[index]:
                i = skip[i]
            else:
                i += 1
        return n_out
    while i < n_nodes:
        d_row = cell[i, 0]
        d_col = cell[i, 1]
        r = row + d_row
        c = col + d_col
        if not (0 <= r < height and 0 <= c < width):
            # Every cell a line looks at lies in the box spanned by the viewer and
            # the line's end: below an outside cell, every line ends outside.
            i = skip[i]
            continue
        index = base + d_row * width + d_col
        node_flags = flags[i]
        if node_flags & FLAG_DIAGONAL:
            beside_a = index + parent[i, 1] - d_col
            beside_b = index + (parent[i, 0] - d_row) * width
            if occupied[beside_a] and occupied[beside_b]:
                i = skip[i]
                continue
        if node_flags & FLAG_TARGET:
            out[n_out] = index
            n_out += 1
        if occupied[index]:
            i = skip[i]
        else:
            i += 1
    return n_out


@numba.njit(cache=True, nogil=True)
def is_visible_kernel(
    occupied: npt.NDArray[np.bool_], row: int, col: int, target_row: int, target_col: int
) -> bool:
    """Whether ``(target_row, target_col)`` is visible from ``(row, col)``; both in the grid.

    Walks the line directly (no table), as a second, independent reading of the
    definition.
    """
    d_row = target_row - row
    d_col = target_col - col
    step_r = 1 if d_row >= 0 else -1
    step_c = 1 if d_col >= 0 else -1
    a_row = abs(d_row)
    a_col = abs(d_col)
    n = max(a_row, a_col)
    prev_r = row
    prev_c = col
    for i in range(1, n + 1):
        if a_row >= a_col:
            r = row + step_r * i
            c = col + step_c * _line_minor_compiled(i, n, a_col)
        else:
            r = row + step_r * _line_minor_compiled(i, n, a_row)
            c = col + step_c * i
        if r != prev_r and c != prev_c and occupied[r, prev_c] and occupied[prev_r, c]:
            return False
        if i < n and occupied[r, c]:
            return False
        prev_r = r
        prev_c = c
    return True


@numba.njit(cache=True, nogil=True)
def in_sight_kernel(
    occupied: npt.NDArray[np.bool_],
    row: int,
    col: int,
    target_rows: npt.NDArray[np.int64],
    target_cols: npt.NDArray[np.int64],
    candidates: npt.NDArray[np.bool_],
    out: npt.NDArray[np.bool_],
) -> int:
    """``out[k]`` = ``candidates[k]`` and target ``k`` is visible from ``(row, col)``.

    One line walk (:func:`is_visible_kernel`) per candidate: for a few targets near a
    viewer this is far cheaper than the viewer's whole disk
    (:func:`visible_cells_kernel`), and gives the same answer for every cell of it.
    ``occupied`` is the 2-D grid; the viewer and the targets lie in it.

    Returns:
        How many targets are in sight.
    """
    n_seen = 0
    for k in range(target_rows.shape[0]):
        seen = candidates[k] and is_visible_kernel(
            occupied, row, col, target_rows[k], target_cols[k]
        )
        out[k] = seen
        if seen:
            n_seen += 1
    return n_seen
