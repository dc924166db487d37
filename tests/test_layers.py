"""The trace schema and the pictures are apart (issue 18, step 1).

``mrexplore.trace`` is the format of ``trace.npz``; the simulator writes it and
``mrexplore.viz`` reads it, and neither imports the other: ``import mrexplore.sim``
needs no matplotlib, and ``RunRecord.save`` writes data only. The pictures come
from :func:`mrexplore.save_run`, which the CLI and :func:`mrexplore.run` call.
"""

from __future__ import annotations

import ast
import json
import subprocess
import sys
from pathlib import Path

import pytest

import mrexplore
import mrexplore.sim.record as record_module
import mrexplore.trace as trace_module
from mrexplore.cli import main
from mrexplore.rundir import RUN_FILE_KINDS, RunDirError
from mrexplore.sim import Scenario, simulate

SRC = Path(mrexplore.__file__).resolve().parent
SMALL = Scenario(map="office", size=(24, 24), robots=2, seed=1, max_ticks=15)


def _imported_modules(path: Path) -> set[str]:
    """Every module ``path`` imports, at the top or inside a function (absolute names)."""
    names: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:  # relative: resolve against the file's package
                package = path.parent.relative_to(SRC.parent).parts
                base = ".".join(package[: len(package) - node.level + 1])
                module = f"{base}.{node.module}" if node.module else base
            else:
                module = node.module or ""
            names.add(module)
            names.update(f"{module}.{alias.name}" for alias in node.names)
    return names


def test_sim_sources_import_nothing_of_viz() -> None:
    sources = sorted((SRC / "sim").glob("*.py"))
    assert sources
    for path in sources:
        drawing = {
            name for name in _imported_modules(path) if name.split(".")[:2] == ["mrexplore", "viz"]
        }
        assert not drawing, f"{path.name} imports {sorted(drawing)}"


def test_the_schema_module_imports_no_other_part_of_mrexplore() -> None:
    own = {n for n in _imported_modules(SRC / "trace.py") if n.split(".")[0] == "mrexplore"}
    assert own == set()


def test_import_sim_and_save_load_no_matplotlib_nor_viz(tmp_path: Path) -> None:
    # A fresh interpreter: the test process itself has imported viz long ago.
    script = f"""
import json, sys
from pathlib import Path

def drawing():
    return sorted(
        m for m in sys.modules
        if m.split(".")[0] == "matplotlib" or m.startswith("mrexplore.viz")
    )

import mrexplore.sim
after_import = drawing()
from mrexplore.cli import main
from mrexplore.rundir import RUN_FILE_KINDS, RunDirError
from mrexplore.sim import Scenario, simulate
record = simulate(Scenario(map="office", size=(24, 24), robots=2, seed=1, max_ticks=15))
written = record.save(Path({str(tmp_path)!r}) / "run")
after_save = drawing()
print(json.dumps({{
    "after_import": after_import,
    "after_save": after_save,
    "written": sorted(written),
    "files": sorted(p.name for p in (Path({str(tmp_path)!r}) / "run").iterdir()),
}}))
"""
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=300, check=False
    )
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout.strip().splitlines()[-1])
    assert report["after_import"] == []
    assert report["after_save"] == []  # RunRecord.save writes data only
    assert report["written"] == ["result", "trace"]
    assert report["files"] == ["result.json", "trace.npz"]


@pytest.mark.parametrize(
    "name",
    [
        "OPTIONAL_TRACE_ARRAYS",
        "REQUIRED_TRACE_ARRAYS",
        "component_labels",
        "load_trace",
        "n_link_pairs",
        "pack_links",
        "save_trace",
        "unpack_links",
    ],
)
def test_the_schema_is_still_importable_from_sim_record(name: str) -> None:
    assert getattr(record_module, name) is getattr(trace_module, name)
    assert name in record_module.__all__


def test_save_run_and_run_write_data_and_pictures(tmp_path: Path) -> None:
    record = simulate(SMALL)
    written = mrexplore.save_run(record, tmp_path / "both", gif=True)
    assert list(written) == ["result", "trace", "final", "gif"]
    assert all(RUN_FILE_KINDS[path.name] == kind for kind, path in written.items())
    names = sorted(p.name for p in (tmp_path / "both").iterdir())
    assert names == ["final.png", "result.json", "run.gif", "trace.npz"]
    data = record.save(tmp_path / "data")
    assert sorted(p.name for p in (tmp_path / "data").iterdir()) == ["result.json", "trace.npz"]
    for kind in ("result", "trace"):  # the same data files either way
        assert data[kind].read_bytes() == written[kind].read_bytes()
    result = mrexplore.run(SMALL, str(tmp_path / "api"))
    assert sorted(p.name for p in (tmp_path / "api").iterdir()) == [
        "final.png",
        "result.json",
        "trace.npz",
    ]
    assert result["status"] == json.loads((tmp_path / "api" / "result.json").read_text())["status"]


def test_the_cli_runs_through_mrexplore_run(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    calls: list[dict[str, object]] = []
    real_run = mrexplore.run

    def spy(scenario: object, out_dir: str | None = None, **options: object) -> dict[str, object]:
        calls.append({"out_dir": out_dir, **options})
        return real_run(scenario, out_dir, **options)  # type: ignore[arg-type]

    monkeypatch.setattr(mrexplore, "run", spy)
    out = tmp_path / "cli"
    args = ["run", "--map", "sheng40", "--robots", "2", "--max-ticks", "20", "--out", str(out)]
    assert main([*args, "--gif", "--belief-panels"]) == 0
    assert calls == [
        {
            "out_dir": str(out),
            "gif": True,
            "mp4": False,
            "belief_panels": True,
            "force": False,
            "option": "--out",
        }
    ]
    lines = [line.split() for line in capsys.readouterr().out.splitlines()]
    assert ["gif", str(out / "run.gif")] in lines and ["trace", str(out / "trace.npz")] in lines


def test_run_refuses_a_folder_that_holds_a_run_and_keeps_it(tmp_path: Path) -> None:
    out = tmp_path / "kept"
    mrexplore.run(SMALL, str(out))
    before = (out / "result.json").read_bytes()
    with pytest.raises(RunDirError, match=r"^out_dir .*already holds a run"):
        mrexplore.run(SMALL, str(out), gif=True)
    assert (out / "result.json").read_bytes() == before and not (out / "run.gif").exists()
    mrexplore.run(SMALL, str(out), gif=True, belief_panels=True, force=True)
    assert (out / "run.gif").exists()
