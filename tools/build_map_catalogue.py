"""Build (or check) the shipped map files of ``mrexplore/grid/data`` from a map collection.

Usage::

    python tools/build_map_catalogue.py SOURCE_DIR          # write the files
    python tools/build_map_catalogue.py SOURCE_DIR --check  # only compare

``SOURCE_DIR`` is a folder holding the original files (ROS ``map_server`` YAML +
PGM pairs, MovingAI ``.map`` files, licence texts in ``licenses/``), in any
layout: every original is found by the SHA-256 digest the catalogue records
(:data:`mrexplore.grid.catalogue.CATALOGUE`), so a renamed or moved copy is
found and a changed one is refused.

ROS images become 8-bit greyscale PNG with every pixel value kept; the YAML is
the original with ``image:`` pointing to the PNG and a header saying so. After
writing, every shipped map is loaded and compared cell for cell (occupancy,
resolution, origin, crop) with the original. MovingAI maps and licences are
copied byte for byte. The data folder's ``README.md`` (credits) is written from
the catalogue.
"""

from __future__ import annotations

import argparse
import hashlib
import shutil
import sys
from pathlib import Path

import numpy as np
from PIL import Image

from mrexplore.grid.catalogue import CATALOGUE, DATA_DIR, MapEntry
from mrexplore.grid.io import load_map


def _digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _find_originals(source: Path) -> dict[str, Path]:
    wanted = {entry.source_sha256 for entry in CATALOGUE}
    found: dict[str, Path] = {}
    for path in sorted(source.rglob("*")):
        if path.is_file() and path.suffix.lower() in (".pgm", ".map"):
            digest = _digest(path)
            if digest in wanted:
                found.setdefault(digest, path)
    return found


def _shipped_yaml(entry: MapEntry, original_yaml: Path, png_name: str) -> str:
    lines = original_yaml.read_text(encoding="utf-8").splitlines()
    out = [
        f"# mrexplore catalogue map {entry.name!r}: {entry.credit}",
        f"# Image converted losslessly from {entry.source_file} (PGM, sha256",
        f"# {entry.source_sha256}) to 8-bit greyscale PNG; every pixel value kept.",
    ]
    replaced = False
    for line in lines:
        if line.strip().startswith("image:"):
            out.append(f"image: {png_name}")
            replaced = True
        else:
            out.append(line)
    if not replaced:
        raise SystemExit(f"{original_yaml}: no 'image:' line")
    return "\n".join(out) + "\n"


def _same_map(original: Path, shipped: Path) -> str:
    """An empty string when both files load to the same map, else what differs."""
    a, b = load_map(original), load_map(shipped)
    if a.occupied.shape != b.occupied.shape or not np.array_equal(a.occupied, b.occupied):
        return "occupancy differs"
    if a.resolution_m != b.resolution_m:
        return f"resolution {a.resolution_m} != {b.resolution_m}"
    for key in ("origin", "crop", "border_added"):
        if a.meta.get(key) != b.meta.get(key):
            return f"meta[{key!r}] {a.meta.get(key)} != {b.meta.get(key)}"
    return ""


def _credits_readme() -> str:
    rows = [
        "# Maps shipped with mrexplore",
        "",
        "Maps made by others, shipped so that mrexplore runs on real buildings and",
        "standard benchmark grids. Load one by name (`mrexplore run --map intel`,",
        '`mrexplore.maps.load("intel")`); `mrexplore maps` lists them with their sizes.',
        "Credit a map's source wherever you show it. Licence texts are in `licenses/`.",
        "ROS images are stored as lossless PNG (every pixel value of the original PGM",
        "kept); MovingAI files are unchanged. `source_sha256` in",
        "`mrexplore/grid/catalogue.py` is the digest of each original file.",
        "",
        "| name | file | what | source | licence | credit |",
        "|---|---|---|---|---|---|",
    ]
    for entry in CATALOGUE:
        rows.append(
            f"| `{entry.name}` | `{entry.file}` | {entry.description} | {entry.source} "
            f"| {entry.licence} (`licenses/{entry.licence_file}`) | {entry.credit} |"
        )
    notes = [f"- `{e.name}`: {e.note}" for e in CATALOGUE if e.note and e.kind == "ros"]
    return "\n".join([*rows, "", "Notes:", "", *notes, ""])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("source", type=Path, help="folder with the original map files")
    parser.add_argument("--check", action="store_true", help="compare only, write nothing")
    args = parser.parse_args(argv)
    originals = _find_originals(args.source)
    problems: list[str] = []
    DATA_DIR.mkdir(parents=True, exist_ok=True)
    (DATA_DIR / "licenses").mkdir(exist_ok=True)
    for entry in CATALOGUE:
        original = originals.get(entry.source_sha256)
        if original is None:
            problems.append(f"{entry.name}: no file with sha256 {entry.source_sha256}")
            continue
        licence = next(args.source.rglob(entry.licence_file), None)
        if licence is None:
            problems.append(f"{entry.name}: licence file {entry.licence_file} not found")
        elif not args.check:
            shutil.copyfile(licence, entry.licence_path)
        if entry.kind == "movingai":
            if not args.check:
                shutil.copyfile(original, entry.path)
            if _digest(entry.path) != entry.source_sha256:
                problems.append(f"{entry.name}: shipped file differs from {original}")
            continue
        original_yaml = original.with_suffix(".yaml")
        png = entry.path.with_suffix(".png")
        if not args.check:
            with Image.open(original) as image:
                if image.mode != "L":
                    raise SystemExit(f"{original}: expected an 8-bit greyscale PGM")
                image.save(png, "PNG", optimize=True)
            entry.path.write_text(_shipped_yaml(entry, original_yaml, png.name), encoding="utf-8")
        with Image.open(original) as a, Image.open(png) as b:
            if not np.array_equal(np.asarray(a), np.asarray(b)):
                problems.append(f"{entry.name}: PNG pixels differ from {original}")
        if difference := _same_map(original_yaml, entry.path):
            problems.append(f"{entry.name}: {difference}")
    if not args.check:
        (DATA_DIR / "README.md").write_text(_credits_readme(), encoding="utf-8")
    for problem in problems:
        print(problem, file=sys.stderr)
    total = sum(p.stat().st_size for p in DATA_DIR.rglob("*") if p.is_file())
    print(f"{len(CATALOGUE)} maps, {total / 1e3:.0f} kB in {DATA_DIR}; {len(problems)} problems")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
