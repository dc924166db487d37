"""The real maps that ship inside the package, and the folders of a user's own maps.

Sixteen maps made by others ship as package data (``mrexplore/grid/data``): seven
ROS ``map_server`` maps of real or simulated buildings and nine MovingAI grid
benchmark maps. Each :class:`MapEntry` names its file, where it comes from, its
licence (the licence text ships beside it, in ``data/licenses``) and the credit
line that goes wherever the map is shown. The public face of this table is
:mod:`mrexplore.maps` (``mrexplore.maps.load("intel")``); the simulator resolves
``--map NAME`` through :func:`resolve_map_name`.

How the files were made from their sources (``tools/build_map_catalogue.py``
does it and checks it): ROS images are stored as 8-bit greyscale PNG with every
pixel value kept (PNG is lossless; the YAML points to the PNG and keeps its
thresholds, so the trinary classification is the same cell for cell), which takes
the seven images from 3.5 MB to 0.18 MB. MovingAI maps are copied unchanged.
``source_sha256`` is the digest of the original file, so anyone holding the source
can check that the shipped map is the published one.

A user's own maps load by name too: every folder listed in ``$MREXPLORE_MAPS``
(separated by ``os.pathsep``) is searched for ``<name>.yaml``, ``.yml``, ``.map``,
``.json``, ``.pgm`` or ``.png``. Catalogue names come first.
"""

from __future__ import annotations

import hashlib
import os
from dataclasses import dataclass
from pathlib import Path

__all__ = [
    "CATALOGUE",
    "DATA_DIR",
    "MAPS_ENV",
    "MapEntry",
    "credit_for_file",
    "lookup",
    "resolve_map_name",
    "user_map_dirs",
    "user_maps",
]

#: The folder of the shipped map files, licences and credits.
DATA_DIR = Path(__file__).resolve().parent / "data"
#: Environment variable naming folders of a user's own maps (``os.pathsep``-separated).
MAPS_ENV = "MREXPLORE_MAPS"
#: File extensions :func:`mrexplore.grid.io.load_map` reads (any case).
MAP_SUFFIXES = (".yaml", ".yml", ".pgm", ".png", ".bmp", ".map", ".json")
#: File kinds a user map folder is searched for, in this order.
USER_MAP_SUFFIXES = (".yaml", ".yml", ".map", ".json", ".pgm", ".png")
_PATH_SUFFIXES = frozenset(MAP_SUFFIXES)


@dataclass(frozen=True)
class MapEntry:
    """One shipped map: its file, provenance and licence.

    Attributes:
        name: the short name (``--map NAME``), also the stem of the shipped file.
        file: the shipped file, relative to :data:`DATA_DIR` (the YAML for ROS maps).
        kind: ``"ros"`` (map_server YAML + image) or ``"movingai"`` (``.map``).
        description: what the map shows.
        source: repository and path (or package) the map was copied from.
        source_file: the original file (the image for ROS maps), whose digest is
            ``source_sha256``.
        licence: SPDX id (or short name) of the licence.
        licence_file: the licence text shipped in ``data/licenses``.
        credit: the attribution line reports and plots show.
        note: anything a user must know (an assumed resolution, a written YAML).
    """

    name: str
    file: str
    kind: str
    description: str
    source: str
    source_file: str
    source_sha256: str
    licence: str
    licence_file: str
    credit: str
    note: str = ""

    @property
    def path(self) -> Path:
        """The shipped file (pass it to :func:`~mrexplore.grid.io.load_map`)."""
        return DATA_DIR / self.file

    @property
    def licence_path(self) -> Path:
        return DATA_DIR / "licenses" / self.licence_file


_INTEL = (
    "Intel Research Lab, Seattle: map from gondsm/mrgs_compression_benchmark, "
    "built from the Freiburg SLAM logs (CC BY 1.0)"
)
_NAV2 = "ros-navigation/navigation2 nav2_bringup (Apache-2.0)"
_MOVINGAI = "N. Sturtevant, MovingAI MAPF benchmark (movingai.com), via Kei18/pibt2 (MIT)"
_PIBT2 = "Kei18/pibt2 (MovingAI MAPF benchmark, movingai.com)"
_PIBT2_LICENCE = "Kei18__pibt2__LICENCE.txt"
_NAV2_LICENCE = "ros-navigation__navigation2__LICENSE"


def _nav2(name: str, sha256: str, description: str) -> MapEntry:
    """A map of Nav2's ``nav2_bringup/maps/``: ``name.pgm`` with a ``name.yaml``."""
    return MapEntry(
        name=name,
        file=f"{name}.yaml",
        kind="ros",
        description=description,
        source="ros-navigation/navigation2, nav2_bringup/maps/",
        source_file=f"{name}.pgm",
        source_sha256=sha256,
        licence="Apache-2.0",
        licence_file=_NAV2_LICENCE,
        credit=f"Nav2 {name}: " + _NAV2,
    )


def _movingai(name: str, sha256: str, description: str, credit_extra: str = "") -> MapEntry:
    return MapEntry(
        name=name,
        file=f"{name}.map",
        kind="movingai",
        description=description,
        source=_PIBT2,
        source_file=f"{name}.map",
        source_sha256=sha256,
        licence="MIT",
        licence_file=_PIBT2_LICENCE,
        credit=_MOVINGAI + credit_extra,
        note="unitless cells",
    )


#: Every shipped map, ROS maps first, then MovingAI maps.
CATALOGUE: tuple[MapEntry, ...] = (
    MapEntry(
        name="intel",
        file="intel.yaml",
        kind="ros",
        description="Intel Research Lab, Seattle: ring corridor, many small rooms (real, SLAM)",
        source="gondsm/mrgs_compression_benchmark, pgm/intel.pgm",
        source_file="intel.pgm",
        source_sha256="3f9fc47e441506b81aec3877c4783560a129ca02fd2b8b774545331058be8c71",
        licence="CC-BY-1.0",
        licence_file="gondsm__mrgs_compression_benchmark__pgm_licence.txt",
        credit=_INTEL,
        note="resolution 0.05 m assumed (GMapping default; the source states none)",
    ),
    MapEntry(
        name="aws-small-house",
        file="aws-small-house.yaml",
        kind="ros",
        description="small house, rooms and doors (simulated world mapped by SLAM)",
        source="aws-robotics/aws-robomaker-small-house-world, maps/",
        source_file="map.pgm",
        source_sha256="4406c72e26c2ef743c8976406495bebc975327f3e322b57c8344f9076a2fe41c",
        licence="MIT-0",
        licence_file="aws-robotics__aws-robomaker-small-house-world__LICENSE",
        credit="AWS RoboMaker small house: aws-robotics/aws-robomaker-small-house-world (MIT-0)",
    ),
    MapEntry(
        name="willow-full",
        file="willow-full.yaml",
        kind="ros",
        description="Willow Garage full floor: offices, corridors, open area (real)",
        source="ros-planning/navigation_tutorials, navigation_stage/stage_config/maps/",
        source_file="willow-full.pgm",
        source_sha256="d34c9ab9789841d96dd549d26a7164069c4c6cbfe03f18709f0812a367fa84ca",
        licence="BSD",
        licence_file="ros-planning__navigation_tutorials__navigation_stage_package.xml"
        ".license-line",
        credit="Willow Garage: ros-planning/navigation_tutorials (BSD)",
        note="YAML written for the collection (the source loads it as `map_server ... 0.1`)",
    ),
    MapEntry(
        name="willow-2010",
        file="willow-2010.yaml",
        kind="ros",
        description="Willow Garage office, SLAM with ray artefacts; walls in grey levels",
        source="turtlebot/turtlebot_apps, turtlebot_navigation/maps/",
        source_file="willow-2010-02-18-0.10.pgm",
        source_sha256="d7644ea5eabbbc77dcb6f136774f9b159a6514151f9c411bbd6c383f592bd6e0",
        licence="BSD",
        licence_file="turtlebot__turtlebot_apps__turtlebot_navigation_package.xml.license-line",
        credit="Willow Garage: turtlebot/turtlebot_apps (BSD)",
    ),
    _nav2(
        "depot",
        "71bbac79cfc2f5db89095182bfa86b29d96b07d4ed3b7726e513ed57afffc851",
        "open hall with scattered obstacles",
    ),
    _nav2(
        "warehouse",
        "934ce2ca1feacc2216b68142349c6ebb3e46cc7c76fd80a9c2d2a6fb85ba7ff7",
        "shelf rows and aisles",
    ),
    MapEntry(
        name="lse-arena",
        file="lse-arena.yaml",
        kind="ros",
        description="tiny test arena, one inner wall (smoke tests)",
        source="ros-planning/navigation_tutorials, roomba_stage/maps/lse_arena.pgm",
        source_file="lse_arena.pgm",
        source_sha256="0b2b639da59f2b301af41bcdb67330d6f41ae8fb2a9bf2faab071e9887cea986",
        licence="BSD",
        licence_file="ros-planning__navigation_tutorials__roomba_stage_package.xml.license-line",
        credit="LSE arena: ros-planning/navigation_tutorials (BSD)",
    ),
    _movingai(
        "room-32-32-4",
        "f107fefbf63c7a1a3753e4a033452301a1cdd7043cab7f45e4ed0e7dec1e90a9",
        "8x8 grid of tiny rooms with doors",
    ),
    _movingai(
        "room-64-64-8",
        "56946a2411a64631f4ab7ca8dd17439e619ad066fc1d2bf2fd19516fc24f28dc",
        "8x8 grid of rooms (office-like)",
    ),
    _movingai(
        "room-64-64-16",
        "1ba9cc47e29b59c27b1b8afffaa0e7e582c6d3ac27c87278695f9002dc418c0a",
        "4x4 grid of larger rooms",
    ),
    _movingai(
        "maze-128-128-10",
        "2281ef15df0c94efc79b7c62f0c60ce4cb22c43c2cc584226d307c7676d53986",
        "maze, 10-cell corridors",
    ),
    _movingai(
        "random-64-64-10",
        "b31c671228f884a113ca11c41b83630dc042e58e07f9b36da74ec508f82a5659",
        "10% random obstacles",
    ),
    _movingai(
        "warehouse-20-40-10-2-2",
        "eae2a3f5298b1e113bfc32b5b4404f5de5105365d237df63cc9dc9e2d1c73713",
        "warehouse shelf grid",
    ),
    _movingai(
        "den312d",
        "1b3d72a358329a9a37d0aed62ad2668ee7882c4c745c73dc8b4f5d75493c79c4",
        "Dragon Age: Origins dungeon, rooms and corridors",
        "; level of the game Dragon Age: Origins (BioWare)",
    ),
    _movingai(
        "ht_chantry",
        "0aa95f3f8701eea7938b8ed84a38fa17d4eb7fe0a727ecd43edf413f3774ccc0",
        "Dragon Age 2 building, halls and rooms",
        "; level of the game Dragon Age 2 (BioWare)",
    ),
    _movingai(
        "Berlin_1_256",
        "1e381d55ea4c69b9d6ffac00dc3d37e17d29384a002ae4175b190394e2a302c0",
        "Berlin streets and blocks",
        "; street map of Berlin",
    ),
)


def _key(name: str) -> str:
    """Names match without regard to case, and ``_`` matches ``-``."""
    return name.strip().lower().replace("_", "-")


_BY_KEY: dict[str, MapEntry] = {_key(entry.name): entry for entry in CATALOGUE}
# Credit follows a file by what it is, not by what it is called: a file of the data
# folder by its shipped name, any other file only if its bytes are an original's.
_CREDIT_BY_SHIPPED_FILE: dict[str, str] = {}
for _entry in CATALOGUE:
    _CREDIT_BY_SHIPPED_FILE[_entry.file] = _entry.credit
    _CREDIT_BY_SHIPPED_FILE[Path(_entry.file).with_suffix(".png").name] = _entry.credit
_CREDIT_BY_DIGEST: dict[str, str] = {entry.source_sha256: entry.credit for entry in CATALOGUE}
#: Files larger than every original are not hashed (a user's big map is read once).
_LARGEST_ORIGINAL_BYTES = 2_000_000


def lookup(name: str) -> MapEntry | None:
    """The catalogue entry called ``name`` (case-insensitive, ``_`` = ``-``), or ``None``.

    >>> lookup("LSE_arena").name
    'lse-arena'
    >>> lookup("nowhere") is None
    True
    """
    return _BY_KEY.get(_key(name))


def credit_for_file(path: Path) -> str:
    """The credit line of a catalogue map file, else ``""``.

    A file of the package's data folder is credited by its name; any other file
    only when its bytes are those of an original (SHA-256 ``source_sha256``), so a
    copy of the source collection keeps its credit and a user's own ``intel.yaml``
    gets none. (A ROS YAML is matched through its image.)
    """
    try:
        resolved = path.resolve()
        if resolved.parent == DATA_DIR:
            return _CREDIT_BY_SHIPPED_FILE.get(resolved.name, "")
        if not resolved.is_file() or resolved.stat().st_size > _LARGEST_ORIGINAL_BYTES:
            return ""
        digest = hashlib.sha256(resolved.read_bytes()).hexdigest()
    except OSError:
        return ""
    return _CREDIT_BY_DIGEST.get(digest, "")


def user_map_dirs() -> list[Path]:
    """The folders named by ``$MREXPLORE_MAPS`` that exist, in order."""
    value = os.environ.get(MAPS_ENV, "")
    return [Path(part) for part in value.split(os.pathsep) if part and Path(part).is_dir()]


def user_maps() -> dict[str, Path]:
    """Every map file of the user's folders by stem (the first folder wins)."""
    found: dict[str, Path] = {}
    for folder in user_map_dirs():
        for suffix in USER_MAP_SUFFIXES:
            for file in sorted(folder.glob(f"*{suffix}")):
                found.setdefault(file.stem, file)
    return found


def _looks_like_path(name: str) -> bool:
    # Only a map file's extension makes a path: "willow-2010-02-18-0.10" is a name.
    return "/" in name or os.sep in name or Path(name).suffix.lower() in _PATH_SUFFIXES


def resolve_map_name(name: str) -> Path | None:
    """The file a bare map name stands for: a catalogue map, else a user map, else ``None``.

    A name with a folder separator or a map file's extension (``.yaml``, ``.map``,
    ...) is a path, never a name.

    >>> resolve_map_name("intel").name
    'intel.yaml'
    >>> resolve_map_name("intel.yaml") is None
    True
    """
    if _looks_like_path(name):
        return None
    entry = lookup(name)
    if entry is not None:
        return entry.path
    return user_maps().get(name)
