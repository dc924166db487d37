"""Seeded generators of synthetic worlds.

Every generator has the signature ``fn(width, height, rng) -> occupied`` where
``width`` and ``height`` are in cells, ``rng`` is a :class:`numpy.random.Generator`
and ``occupied`` is an ``height x width`` bool array (``True`` = occupied, row 0
at the top) whose outer ring is occupied and whose free cells form **one**
4-connected component (smaller free pockets are filled). 4-connectivity is the
reachability of 8-connected motion without corner cutting.

Look generators up by id in :data:`GENERATORS`, or build a
:class:`~mrexplore.grid.occupancy.GridMap` directly with :func:`generate_map`.
The same id, size and seed always give the same map.

>>> m = generate_map("maze", 40, 30, seed=1)
>>> m.shape, m.source
((30, 40), 'generator:maze(40x30, seed=1)')
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from mrexplore.errors import ScenarioError
from mrexplore.grid.components import largest_free_component
from mrexplore.grid.occupancy import BoolGrid, GridMap
from mrexplore.registry import Registry

__all__ = [
    "GENERATORS",
    "MAX_GENERATED_SIDE",
    "MIN_GENERATED_SIDE",
    "GeneratorFn",
    "GeneratorInfo",
    "blank",
    "cityblock",
    "corridor",
    "generate_map",
    "list_generators",
    "maze",
    "office",
    "sheng40",
    "unstructured",
]

#: Smallest accepted width or height of a generated map, in cells.
MIN_GENERATED_SIDE = 8
#: Largest accepted width or height of a generated map, in cells.
MAX_GENERATED_SIDE = 10_000

GeneratorFn = Callable[[int, int, np.random.Generator], BoolGrid]


# --------------------------------------------------------------------------- helpers


def _walled(width: int, height: int) -> BoolGrid:
    """An empty room: only the outer ring occupied."""
    occupied = np.zeros((height, width), dtype=bool)
    occupied[0, :] = occupied[-1, :] = True
    occupied[:, 0] = occupied[:, -1] = True
    return occupied


def _finalize(occupied: BoolGrid) -> BoolGrid:
    """Close the outer ring and fill every free cell outside the largest component."""
    occupied = occupied.copy()
    occupied[0, :] = occupied[-1, :] = True
    occupied[:, 0] = occupied[:, -1] = True
    keep = largest_free_component(occupied)
    if not keep.any():  # defensive: generators always leave free space
        return _walled(occupied.shape[1], occupied.shape[0])
    return ~keep


def _landscape(width: int, height: int, rng: np.random.Generator, layout: GeneratorFn) -> BoolGrid:
    """Run ``layout`` with its long axis horizontal, then turn the result back."""
    if height > width:
        return layout(height, width, rng).T.copy()
    return layout(width, height, rng)


def _two_rooms(width: int, height: int) -> BoolGrid:
    """Fallback for maps too small for a structured layout: two rooms and a door."""
    occupied = _walled(width, height)
    if width >= 7 and height >= 6:
        wall = width // 2
        occupied[1:-1, wall] = True
        door = height // 2 - 1
        occupied[door : door + 2, wall] = False
    return occupied


# --------------------------------------------------------------------------- blank


def blank(width: int, height: int, rng: np.random.Generator) -> BoolGrid:
    """An empty room: walls on the outer ring only. ``rng`` is not used."""
    del rng
    return _walled(width, height)


# --------------------------------------------------------------------------- unstructured


def _shape_mask(kind: int, rows: int, cols: int, rng: np.random.Generator) -> BoolGrid:
    """A ``rows x cols`` mask of one obstacle: rectangle, disc, L-shape or blob."""
    if kind == 0:
        return np.ones((rows, cols), dtype=bool)
    yy, xx = np.mgrid[0:rows, 0:cols]
    cy, cx = (rows - 1) / 2.0, (cols - 1) / 2.0
    if kind == 1:  # ellipse filling the box
        ry, rx = max(rows / 2.0, 0.5), max(cols / 2.0, 0.5)
        return ((yy - cy) / ry) ** 2 + ((xx - cx) / rx) ** 2 <= 1.0
    if kind == 2:  # L-shape, randomly mirrored
        thick = max(1, min(rows, cols) // 3)
        mask = (yy < thick) | (xx < thick)
        if rng.random() < 0.5:
            mask = mask[::-1, :]
        if rng.random() < 0.5:
            mask = mask[:, ::-1]
        return np.ascontiguousarray(mask)
    # blob: a disc whose radius wobbles with the angle
    radius = max(min(rows, cols) / 2.0, 1.0)
    angle = np.arctan2(yy - cy, xx - cx)
    phases = rng.uniform(0, 2 * np.pi, size=3)
    wobble = (
        1.0
        + 0.25 * np.sin(2 * angle + phases[0])
        + 0.15 * np.sin(3 * angle + phases[1])
        + 0.10 * np.sin(5 * angle + phases[2])
    )
    return np.hypot(yy - cy, xx - cx) <= radius * 0.85 * wobble


def unstructured(width: int, height: int, rng: np.random.Generator) -> BoolGrid:
    """Scattered obstacles of varied shapes (rectangles, discs, L-shapes, blobs).

    About 15-25 % of the interior ends up occupied, in the spirit of the
    "unstructured" map of Wu, Puig and García (balanced K-means exploration).
    Obstacle sides scale with the map: from ``min(w, h) / 25`` to ``/ 8`` cells.
    """
    occupied = _walled(width, height)
    inner_h, inner_w = height - 2, width - 2
    target = rng.uniform(0.14, 0.21) * inner_h * inner_w
    side = min(width, height)
    size_min = max(2, side // 25)
    size_max = max(size_min + 1, side // 8)
    filled = 0
    for _attempt in range(100_000):
        if filled >= target:
            break
        kind = int(rng.integers(4))
        rows = min(int(rng.integers(size_min, size_max + 1)), inner_h)
        cols = min(int(rng.integers(size_min, size_max + 1)), inner_w)
        if kind == 0 and rng.random() < 0.5:  # some long thin walls
            if rng.random() < 0.5:
                rows = max(1, rows // 4)
            else:
                cols = max(1, cols // 4)
        top = int(rng.integers(1, height - rows)) if height - rows > 1 else 1
        left = int(rng.integers(1, width - cols)) if width - cols > 1 else 1
        mask = _shape_mask(kind, rows, cols, rng)
        window = occupied[top : top + rows, left : left + cols]
        filled += int(np.count_nonzero(mask & ~window))
        window |= mask
    return _finalize(occupied)


# --------------------------------------------------------------------------- cityblock


def _block_runs(
    length: int, rng: np.random.Generator, streets: tuple[int, int], blocks: tuple[int, int]
) -> list[tuple[int, int]]:
    """``[start, end)`` runs of blocks along one axis, streets between and at both ends."""
    runs: list[tuple[int, int]] = []
    position = 1
    while True:
        position += int(rng.integers(streets[0], streets[1] + 1))
        size = int(rng.integers(blocks[0], blocks[1] + 1))
        if position + size + streets[0] > length - 1:
            break
        runs.append((position, position + size))
        position += size
    if runs:  # centre the pattern so both outer streets have similar widths
        head = runs[0][0] - 1
        tail = (length - 1) - runs[-1][1]
        shift = max(0, (tail - head) // 2)
        runs = [(start + shift, end + shift) for start, end in runs]
    return runs


def _run_index(length: int, runs: list[tuple[int, int]]) -> np.ndarray:
    """Per position: index of the run covering it, or -1."""
    index = np.full(length, -1, dtype=np.int64)
    for number, (start, end) in enumerate(runs):
        index[start:end] = number
    return index


def _gap_index(length: int, runs: list[tuple[int, int]]) -> np.ndarray:
    """Per position: ``k`` if it lies in the street between runs ``k`` and ``k + 1``, else -1."""
    index = np.full(length, -1, dtype=np.int64)
    for number in range(len(runs) - 1):
        index[runs[number][1] : runs[number + 1][0]] = number
    return index


def cityblock(width: int, height: int, rng: np.random.Generator) -> BoolGrid:
    """Rectangular city blocks separated by a grid of streets.

    Streets are 3-4 cells wide on small maps and up to 5-6 on large ones; blocks
    are 2-3.5 times a street's width. About 10 % of blocks are left open (squares),
    and about 8 % of street segments between two blocks are built over, merging
    the blocks. Like the "cityblock" map of Wu, Puig and García.
    """
    side = min(width, height)
    street_min = int(np.clip(3 + side // 150, 3, 5))
    streets = (street_min, street_min + 1)
    blocks = (max(6, 2 * street_min), 3 * (street_min + 1) + side // 100)
    row_runs = _block_runs(height, rng, streets, blocks)
    col_runs = _block_runs(width, rng, streets, blocks)
    occupied = _walled(width, height)
    if not row_runs or not col_runs:
        return occupied
    row_block, col_block = _run_index(height, row_runs), _run_index(width, col_runs)
    row_gap, col_gap = _gap_index(height, row_runs), _gap_index(width, col_runs)
    n_rows, n_cols = len(row_runs), len(col_runs)
    built = rng.random((n_rows, n_cols)) >= 0.10  # False = open square
    merge_right = (rng.random((n_rows, max(n_cols - 1, 1))) < 0.08)[:, : n_cols - 1]
    merge_down = (rng.random((max(n_rows - 1, 1), n_cols)) < 0.08)[: n_rows - 1, :]
    merge_right &= built[:, :-1] & built[:, 1:]
    merge_down &= built[:-1, :] & built[1:, :]

    in_row, in_col = row_block >= 0, col_block >= 0
    rb, cb = np.maximum(row_block, 0), np.maximum(col_block, 0)
    occupied |= in_row[:, None] & in_col[None, :] & built[rb][:, cb]
    if n_cols > 1:
        gap_col = col_gap >= 0
        occupied |= in_row[:, None] & gap_col[None, :] & merge_right[rb][:, np.maximum(col_gap, 0)]
    if n_rows > 1:
        gap_row = row_gap >= 0
        occupied |= gap_row[:, None] & in_col[None, :] & merge_down[np.maximum(row_gap, 0)][:, cb]
    return _finalize(occupied)


# --------------------------------------------------------------------------- office


def _office_layout(width: int, height: int, rng: np.random.Generator) -> BoolGrid:
    """Office floor with horizontal corridors (``width >= height``)."""
    side = height
    corridor_w = int(np.clip(3 + side // 150, 3, 5))
    door_w = 2 if side < 150 else 3
    depth_target = int(np.clip(side // 7, 6, 20))
    available = height - 2

    def depth_for(units: int) -> int:
        return (available - units * (corridor_w + 2) - (units - 1)) // (2 * units)

    units = max(1, round(available / (2 * depth_target + corridor_w + 3)))
    while units > 1 and depth_for(units) < 4:
        units -= 1
    depth = depth_for(units)
    if depth < 3 or width < 12:
        return _two_rooms(width, height)
    extra = available - (units * (2 * depth + corridor_w + 2) + (units - 1))
    depths = np.full(2 * units, depth, dtype=np.int64)
    depths[rng.permutation(2 * units)[:extra]] += 1

    occupied = np.ones((height, width), dtype=bool)
    corridors: list[tuple[int, int]] = []
    room_rows: list[tuple[int, int, int]] = []  # (row0, row1, door wall row)
    y = 1
    for unit in range(units):
        if unit:
            y += 1  # wall between back-to-back rooms
        top = int(depths[2 * unit])
        room_rows.append((y, y + top, y + top))
        y += top + 1
        corridors.append((y, y + corridor_w))
        occupied[y : y + corridor_w, 1 : width - 1] = False
        y += corridor_w + 1
        bottom = int(depths[2 * unit + 1])
        room_rows.append((y, y + bottom, y - 1))
        y += bottom

    # Vertical corridors join the horizontal ones, cutting through inner room rows.
    connectors: list[int] = []
    if units > 1:
        count = max(1, round((width - 2) / 90))
        spacing = (width - 2) / count
        for number in range(count):
            centre = 1 + (number + 0.5) * spacing + rng.uniform(-0.2, 0.2) * spacing
            left = int(np.clip(round(centre) - corridor_w // 2, 2, width - 2 - corridor_w))
            connectors.append(left)
            occupied[corridors[0][0] : corridors[-1][1], left : left + corridor_w] = False
    connectors.sort()

    room_min = max(5, int(0.6 * depth))
    room_max = min(25, max(room_min + 2, int(1.4 * depth)))
    first_row, last_row = room_rows[0][0], room_rows[-1][0]
    for row0, row1, door_row in room_rows:
        cut = connectors if row0 not in (first_row, last_row) else []
        bounds = [1, *[c for left in cut for c in (left - 1, left + corridor_w + 1)], width - 1]
        for seg_start, seg_end in zip(bounds[::2], bounds[1::2], strict=True):
            x = seg_start
            rooms: list[tuple[int, int]] = []
            while x < seg_end:
                room_w = int(rng.integers(room_min, room_max + 1))
                if seg_end - x - room_w < room_min + 1:
                    room_w = seg_end - x
                rooms.append((x, x + room_w))
                x += room_w + 1
            for number, (x0, x1) in enumerate(rooms):
                occupied[row0:row1, x0:x1] = False
                door = min(door_w, x1 - x0)
                door_x = int(rng.integers(x0, x1 - door + 1))
                occupied[door_row, door_x : door_x + door] = False
                if number + 1 < len(rooms) and rng.random() < 0.2:  # door to the next room
                    inner = min(door_w, row1 - row0)
                    door_y = int(rng.integers(row0, row1 - inner + 1))
                    occupied[door_y : door_y + inner, x1] = False
    return occupied


def office(width: int, height: int, rng: np.random.Generator) -> BoolGrid:
    """An office floor: rows of rooms on both sides of corridors, doors into them.

    Corridors (3-5 cells wide) run along the map's long axis and are joined by
    cross corridors roughly every 90 cells; rooms are 6-20 cells deep and 5-25
    cells wide, walls are 1 cell, doors 2 cells (3 on maps of 150+ cells), and
    about one room in five has a second door into its neighbour.
    """
    return _finalize(_landscape(width, height, rng, _office_layout))


# --------------------------------------------------------------------------- corridor


def _rooms_along(
    occupied: BoolGrid,
    rng: np.random.Generator,
    corridor: tuple[int, int, int, int],
    sizes: tuple[int, int],
    door_w: int,
) -> None:
    """Line both long sides of a horizontal corridor ``(row0, row1, col0, col1)`` with rooms.

    Walking along the corridor, each room gets a random length and the largest
    depth (up to a random cap) for which the room and its one-cell wall ring
    touch nothing carved yet; its door opens onto the corridor. Works on a
    transposed view for vertical corridors.
    """
    height, width = occupied.shape
    row0, row1, col0, col1 = corridor
    size_min, size_max = sizes
    for side in (-1, 1):
        wall = row0 - 1 if side < 0 else row1  # the wall row between corridor and rooms
        position = col0
        while position + size_min <= col1:
            length = min(int(rng.integers(size_min, size_max + 1)), col1 - position)
            cap = int(rng.integers((size_min + size_max) // 2, size_max + 1))
            left, right = position - 1, position + length + 1
            if left < 0 or right > width:
                position += 1
                continue
            # Rows from the wall outwards whose cells under the room (and its side walls)
            # are all uncarved; the last clear row becomes the far wall.
            if side < 0:
                strip = occupied[max(0, wall - cap - 1) : wall + 1, left:right][::-1]
            else:
                strip = occupied[wall : min(height, wall + cap + 2), left:right]
            clear_rows = np.asarray(strip.all(axis=1))
            clear = int(np.argmin(clear_rows)) if not clear_rows.all() else int(clear_rows.size)
            depth = min(clear - 2, cap)
            if depth < 3:
                # Skip past the last column that blocks even the shallowest room.
                blocked = np.flatnonzero(~strip[:5].all(axis=0))
                if blocked.size == 0:  # too close to the map's edge on this side
                    break
                position = left + int(blocked[-1]) + 2
                continue
            if side < 0:
                occupied[wall - depth : wall, position : position + length] = False
            else:
                occupied[wall + 1 : wall + 1 + depth, position : position + length] = False
            door = min(door_w, length)
            offset = position + int(rng.integers(0, length - door + 1))
            occupied[wall, offset : offset + door] = False
            position += length + 1


def _corridor_layout(width: int, height: int, rng: np.random.Generator) -> BoolGrid:
    """Main corridor along the long axis, branches off it, rooms along all of them."""
    side = height
    if side < 14 or width < 14:
        return _two_rooms(width, height)
    corridor_w = int(np.clip(2 + side // 100, 2, 4))
    door_w = 2 if side < 200 else 3
    size_min = int(np.clip(side // 12, 4, 10))
    size_max = int(np.clip(side // 4, size_min + 3, 24))
    occupied = np.ones((height, width), dtype=bool)

    low, high = height // 3, max(height // 3 + 1, (2 * height) // 3 - corridor_w)
    main_row = int(rng.integers(low, high))
    main = (main_row, main_row + corridor_w, 1, width - 1)
    occupied[main_row : main_row + corridor_w, 1 : width - 1] = False
    horizontal: list[tuple[int, int, int, int]] = [main]
    vertical: list[tuple[int, int, int, int]] = []

    x = 1 + int(rng.integers(size_min + 1, size_max + 2))
    while x + corridor_w < width - 2:
        directions = [d for d in (-1, 1) if rng.random() < 0.9] or [int(rng.choice([-1, 1]))]
        for direction in directions:
            room = main_row - 2 if direction < 0 else height - 3 - (main_row + corridor_w)
            if room < size_min:
                continue
            length = int(rng.integers(max(size_min, room - size_min), room + 1))
            if direction < 0:
                r0, r1 = main_row - length, main_row
            else:
                r0, r1 = main_row + corridor_w, main_row + corridor_w + length
            occupied[r0:r1, x : x + corridor_w] = False
            vertical.append((r0, r1, x, x + corridor_w))
            # Now and then a side corridor leaves the branch near its far end.
            if rng.random() < 0.3 and length > 2 * size_min:
                along = r0 + 1 if direction < 0 else r1 - corridor_w - 1
                span = int(rng.integers(size_min, 2 * size_max + 1))
                if rng.random() < 0.5:  # to the right; keep a wall column at the far end
                    c0, c1 = x + corridor_w, min(width - 2, x + corridor_w + span)
                    clear = occupied[along - 1 : along + corridor_w + 1, c0 : c1 + 1]
                else:
                    c0, c1 = max(2, x - span), x
                    clear = occupied[along - 1 : along + corridor_w + 1, c0 - 1 : c1]
                if c1 - c0 >= size_min and clear.all():
                    occupied[along : along + corridor_w, c0:c1] = False
                    horizontal.append((along, along + corridor_w, c0, c1))
        x += corridor_w + int(rng.integers(2 * size_min + 3, 2 * size_max + 4))

    for sizes in ((size_min, size_max), (max(3, size_min // 2), max(4, size_min))):
        # The second pass, with small rooms, fills gaps the first one left.
        for row0, row1, col0, col1 in vertical:
            _rooms_along(occupied.T, rng, (col0, col1, row0, row1), sizes, door_w)
        for hall in horizontal:
            _rooms_along(occupied, rng, hall, sizes, door_w)
    return occupied


def corridor(width: int, height: int, rng: np.random.Generator) -> BoolGrid:
    """Long corridors with side rooms, like a hotel or hospital wing.

    A main corridor (2-4 cells wide) runs along the long axis; branches leave it
    at random intervals, sometimes with a side corridor of their own; every
    corridor is lined with rooms (each with one door, 2-3 cells wide) wherever
    they fit. Space no room fits into stays solid.
    """
    return _finalize(_landscape(width, height, rng, _corridor_layout))


# --------------------------------------------------------------------------- maze


def maze(
    width: int, height: int, rng: np.random.Generator, corridor_width: int | None = None
) -> BoolGrid:
    """A perfect maze (exactly one path between two cells), walls 1 cell thick.

    Built with the randomised depth-first "recursive backtracker" on a coarse grid
    of ``corridor_width x corridor_width`` cells, with an explicit stack. The
    default corridor width is 2 cells below 150 cells on the short side and 3
    above. Any leftover strip on the right or bottom (less than one maze cell)
    is occupied, split evenly between both sides.
    """
    side = min(width, height)
    width_cells = corridor_width if corridor_width is not None else (2 if side < 150 else 3)
    width_cells = max(1, min(int(width_cells), (side - 1) // 2 - 1))
    pitch = width_cells + 1
    n_cols, n_rows = (width - 1) // pitch, (height - 1) // pitch
    if n_cols < 1 or n_rows < 1:
        return _walled(width, height)
    off_x = ((width - 1) - n_cols * pitch) // 2
    off_y = ((height - 1) - n_rows * pitch) // 2

    total = n_cols * n_rows
    visited = bytearray(total)
    draws = rng.random(total + 1).tolist()
    start = int(rng.integers(total))
    visited[start] = 1
    stack = [start]
    right_walls: list[int] = []  # cell index whose right wall is opened
    down_walls: list[int] = []  # cell index whose bottom wall is opened
    used = 0
    while stack:
        cell = stack[-1]
        row, col = divmod(cell, n_cols)
        options: list[int] = []
        if col > 0 and not visited[cell - 1]:
            options.append(cell - 1)
        if col + 1 < n_cols and not visited[cell + 1]:
            options.append(cell + 1)
        if row > 0 and not visited[cell - n_cols]:
            options.append(cell - n_cols)
        if row + 1 < n_rows and not visited[cell + n_cols]:
            options.append(cell + n_cols)
        if not options:
            stack.pop()
            continue
        chosen = options[int(draws[used] * len(options))]
        used += 1
        visited[chosen] = 1
        stack.append(chosen)
        low = min(cell, chosen)
        if abs(chosen - cell) == 1:
            right_walls.append(low)
        else:
            down_walls.append(low)

    occupied = np.ones((height, width), dtype=bool)
    steps = np.arange(width_cells)
    interior_rows = (off_y + 1 + np.arange(n_rows)[:, None] * pitch + steps).ravel()
    interior_cols = (off_x + 1 + np.arange(n_cols)[:, None] * pitch + steps).ravel()
    occupied[np.ix_(interior_rows, interior_cols)] = False
    if right_walls:
        rw_row, rw_col = np.divmod(np.asarray(right_walls), n_cols)
        rows = off_y + 1 + rw_row[:, None] * pitch + steps
        cols = np.broadcast_to((off_x + (rw_col + 1) * pitch)[:, None], rows.shape)
        occupied[rows, cols] = False
    if down_walls:
        dw_row, dw_col = np.divmod(np.asarray(down_walls), n_cols)
        cols = off_x + 1 + dw_col[:, None] * pitch + steps
        rows = np.broadcast_to((off_y + (dw_row + 1) * pitch)[:, None], cols.shape)
        occupied[rows, cols] = False
    return _finalize(occupied)


def _maze_default(width: int, height: int, rng: np.random.Generator) -> BoolGrid:
    return maze(width, height, rng)


# --------------------------------------------------------------------------- sheng40

#: Obstacles of :func:`sheng40` as ``(row0, row1, col0, col1)`` in the 40 x 40
#: free square, end exclusive. The paper's figure is unavailable: our choice.
SHENG40_OBSTACLES: tuple[tuple[int, int, int, int], ...] = (
    (8, 20, 8, 16),  # 12 rows x 8 columns, upper left
    (26, 32, 22, 34),  # 6 rows x 12 columns, lower right
)


def sheng40(width: int, height: int, rng: np.random.Generator) -> BoolGrid:
    """The 40 x 40 square with two obstacles of Sheng et al. (2006), §5.

    Sheng, Yang, Tan and Xi, "Distributed multi-robot coordination in area
    exploration", Robotics and Autonomous Systems 54 (2006): "a square of 40 by
    40, with two obstacles in it". The paper's figure is unavailable, so the
    obstacle geometry is our choice (:data:`SHENG40_OBSTACLES`): a 8 x 12 cell
    block (w x h) in the upper left and a 12 x 6 cell block in the lower right.

    The default 42 x 42 grid is a one-cell wall ring around a 40 x 40 free
    square, the paper's area. Other sizes scale the obstacles with the interior.
    Deterministic: ``rng`` is not used.
    """
    del rng
    occupied = _walled(width, height)
    inner_w, inner_h = width - 2, height - 2
    for row0, row1, col0, col1 in SHENG40_OBSTACLES:
        r0 = 1 + round(row0 * inner_h / 40)
        r1 = 1 + max(round(row1 * inner_h / 40), round(row0 * inner_h / 40) + 1)
        c0 = 1 + round(col0 * inner_w / 40)
        c1 = 1 + max(round(col1 * inner_w / 40), round(col0 * inner_w / 40) + 1)
        occupied[r0:r1, c0:c1] = True
    return _finalize(occupied)


# --------------------------------------------------------------------------- registry


@dataclass(frozen=True)
class GeneratorInfo:
    """A registered world generator.

    Attributes:
        name: the id used by :func:`generate_map` and the CLI.
        fn: ``fn(width, height, rng) -> occupied`` (cells, ``True`` = occupied).
        description: one line for ``--help`` and listings.
        default_size: ``(width, height)`` in cells.
    """

    name: str
    fn: GeneratorFn
    description: str
    default_size: tuple[int, int]


GENERATORS: Registry[GeneratorInfo] = Registry(
    "generator",
    "mrexplore.generators",
    id_of=lambda info: info.name,
    summary_of=lambda info: info.description,
)
"""World generators by id (``--map NAME``); plugins: entry-point group
``mrexplore.generators``, each entry point naming a :class:`GeneratorInfo`."""

for _info in (
    GeneratorInfo("blank", blank, "empty room, walls on the border only", (100, 100)),
    GeneratorInfo(
        "unstructured",
        unstructured,
        "scattered obstacles of varied shapes, 15-25% occupied (Wu et al.)",
        (100, 100),
    ),
    GeneratorInfo(
        "cityblock",
        cityblock,
        "rectangular blocks separated by a grid of streets (Wu et al.)",
        (100, 100),
    ),
    GeneratorInfo("office", office, "rooms with doors on both sides of corridors", (120, 80)),
    GeneratorInfo(
        "corridor", corridor, "long branching corridors lined with side rooms", (100, 100)
    ),
    GeneratorInfo(
        "maze", _maze_default, "perfect maze, corridors 2-3 cells, walls 1 cell", (100, 100)
    ),
    GeneratorInfo(
        "sheng40",
        sheng40,
        "40x40 square with two obstacles (Sheng et al. 2006; our obstacle layout)",
        (42, 42),
    ),
):
    GENERATORS.register(_info)


def list_generators() -> list[GeneratorInfo]:
    """All registered generators, sorted by name."""
    return list(GENERATORS.available().values())


def _check_side(what: str, value: object) -> int:
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise ScenarioError(f"--size: {what} must be a whole number of cells, got {value!r}")
    if value < MIN_GENERATED_SIDE:
        raise ScenarioError(
            f"--size: {what} {value} is too small; the minimum is {MIN_GENERATED_SIDE} cells"
        )
    if value > MAX_GENERATED_SIDE:
        raise ScenarioError(
            f"--size: {what} {value} is too large; the maximum is {MAX_GENERATED_SIDE} cells"
        )
    return int(value)


def generate_map(
    name: str, width: int | None = None, height: int | None = None, seed: int = 0
) -> GridMap:
    """Generate a world by generator id.

    Args:
        name: a key of :data:`GENERATORS`.
        width: cells; ``None`` uses the generator's default, or ``height`` if only
            that is given (a square).
        height: cells; likewise.
        seed: non-negative integer seeding ``numpy.random.default_rng``.

    Returns:
        A :class:`GridMap` with ``name`` = the id, no resolution and ``source``
        like ``"generator:office(200x200, seed=3)"``.

    Raises:
        UnknownIdError: no generator has this id.
        ScenarioError: a side is not an integer in 8..10000, or the seed is invalid.
    """
    info = GENERATORS.get(name)  # UnknownIdError names the known ids
    if width is None and height is None:
        width, height = info.default_size
    elif width is None:
        width = height
    elif height is None:
        height = width
    width = _check_side("width", width)
    height = _check_side("height", height)
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise ScenarioError(f"--seed must be a non-negative integer, got {seed!r}")
    rng = np.random.default_rng(int(seed))
    occupied = np.ascontiguousarray(info.fn(width, height, rng), dtype=bool)
    return GridMap(
        occupied=occupied,
        name=name,
        resolution_m=None,
        source=f"generator:{name}({width}x{height}, seed={int(seed)})",
        meta={"generator": name, "seed": int(seed)},
    )
