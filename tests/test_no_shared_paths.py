"""No file of the project points outside the repository to the old shared folders.

Real maps ship inside the package (:mod:`mrexplore.grid.catalogue`); a user has no
folder next to the clone, so code, tests, benchmarks and the README must not name
one. The files searched are the ones git tracks plus untracked files that are not
ignored (so a new file counts before it is committed); without git, the tree is
walked. ``docs/`` is left out: it may tell the history.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
# Built from pieces so that this file does not contain what it searches for.
FORBIDDEN = (".." + "/shared", "shared" + "/maps", "shared" + "/papers")
EXCLUDED_DIRS = {"docs"}
WALK_SKIPPED = {
    ".git",
    ".venv",
    "venv",
    "__pycache__",
    ".pytest_cache",
    ".mypy_cache",
    ".ruff_cache",
    ".hypothesis",
    "build",
    "dist",
    "runs",
}


def _git_files() -> list[Path] | None:
    git = shutil.which("git")
    if git is None:
        return None
    try:
        done = subprocess.run(
            [git, "ls-files", "--cached", "--others", "--exclude-standard", "-z"],
            cwd=REPO,
            capture_output=True,
            check=True,
            timeout=60,
        )
    except (OSError, subprocess.SubprocessError):
        return None
    names = [name for name in done.stdout.decode("utf-8", "surrogateescape").split("\0") if name]
    return [Path(name) for name in names]


def _walked_files() -> list[Path]:
    found = []
    for root, dirs, files in os.walk(REPO):
        dirs[:] = sorted(d for d in dirs if d not in WALK_SKIPPED and not d.endswith(".egg-info"))
        for name in sorted(files):
            found.append((Path(root) / name).relative_to(REPO))
    return found


def project_files() -> list[Path]:
    """Every file of the project, relative to the repository root."""
    files = _git_files()
    return files if files is not None else _walked_files()


def test_the_file_list_is_plausible() -> None:
    files = {path.as_posix() for path in project_files()}
    assert "pyproject.toml" in files
    assert "tests/test_no_shared_paths.py" in files


def test_no_file_outside_docs_names_the_shared_folders() -> None:
    hits = []
    for relative in project_files():
        if relative.parts and relative.parts[0] in EXCLUDED_DIRS:
            continue
        path = REPO / relative
        if not path.is_file():  # deleted in the work tree, not yet staged
            continue
        data = path.read_bytes()
        if b"\0" in data[:8192]:  # binary: images, archives
            continue
        text = data.decode("utf-8", "replace")
        for number, line in enumerate(text.splitlines(), start=1):
            for needle in FORBIDDEN:
                if needle in line:
                    hits.append(
                        f"{relative.as_posix()}:{number}: {needle!r} in {line.strip()[:160]}"
                    )
    assert not hits, "paths to the shared folders outside docs/:\n" + "\n".join(hits)


def test_the_walk_without_git_finds_the_sources() -> None:
    walked = {path.as_posix() for path in _walked_files()}
    assert "tests/test_no_shared_paths.py" in walked
    assert not any(name.startswith((".venv/", ".git/")) for name in walked)
    listed = _git_files()
    if listed is not None:
        sources = {p.as_posix() for p in listed if p.suffix == ".py" and (REPO / p).is_file()}
        assert sources <= walked
