"""The bad-input corpus (tests/inputs/, generated part written by tests/inputs/make_corpus.py): every broken or
absurd scene, wheel–rail scene, calibration configuration, profile file and layer table gives exactly one line
``error: <input>: <what is wrong>`` naming the key, exit code 2, no traceback, nothing on stdout and nothing
written. The valid base documents the corpus is made from are checked too (a corpus of files that fail for
another reason would prove nothing)."""

from __future__ import annotations

import json
import sys
import tomllib
from pathlib import Path

import pytest

INPUTS = Path(__file__).resolve().parent / "inputs"
sys.path.insert(0, str(INPUTS))
import make_corpus


def _expected(folder: str) -> list[tuple[Path, str]]:
    table = tomllib.loads((INPUTS / folder / "expected.toml").read_text(encoding="utf-8"))
    return [(INPUTS / folder / name, fragment) for name, fragment in sorted(table.items())]


def _check(rc: int, captured, path: Path, fragment: str, out: Path) -> None:
    err = captured.err.strip()
    assert rc == 2, (rc, err)
    assert "\n" not in err and err.startswith("error: "), err
    assert "Traceback" not in err
    assert fragment in err, err
    assert f"{path.name}: {path.name}" not in err and err.count(f"{path.name}:") <= 1, err  # named once
    assert captured.out == ""
    assert not out.exists(), "an output was written for a bad input"


def test_every_corpus_file_has_an_expectation():
    for folder in ("bad_scenes_generated", "bad_wheel_rail_scenes", "bad_calibration_configs_generated",
                   "bad_profiles", "bad_layer_tables"):
        files = {p.name for p in (INPUTS / folder).iterdir() if p.name not in ("expected.toml", "good.json")}
        assert files == {p.name for p, _ in _expected(folder)}, folder
    assert sum(len(_expected(f)) for f in ("bad_scenes_generated", "bad_wheel_rail_scenes",
                                           "bad_calibration_configs_generated", "bad_profiles",
                                           "bad_layer_tables")) >= 150


def test_base_documents_are_valid(tmp_path):
    from calibration.config import load_config
    from calibration.pipeline import make_tasks
    from wrlayer.layer_table import LayerTable
    from contact.scenes.scene import load_scene
    from contact.wheel_rail.parse import parse_wheel_rail_scene

    make_corpus.write_toml(tmp_path / "scene.toml", make_corpus.SCENE, "base")
    assert load_scene(tmp_path / "scene.toml").passes.max == 3
    make_corpus.write_toml(tmp_path / "wr.toml", make_corpus.WHEEL_RAIL, "base")
    data = tomllib.loads((tmp_path / "wr.toml").read_text())
    assert len(parse_wheel_rail_scene(data, tmp_path / "wr.toml").cases) == 2
    make_corpus.write_toml(tmp_path / "cfg.toml", make_corpus.CONFIG, "base", [make_corpus.BODY])
    tasks, failed, _ = make_tasks(load_config(tmp_path / "cfg.toml"), tmp_path / "out", plots=False)
    assert len(tasks) == 1 and not failed
    assert len(LayerTable.read(INPUTS / "bad_layer_tables" / "good.json").positions) == 3
    (tmp_path / "crown.prr").write_text(make_corpus.simpack({}), encoding="utf-8")
    (tmp_path / "crown.csv").write_text(make_corpus.csv_text(make_corpus.crown_points()), encoding="utf-8")
    from meshes.profiles import get_profile

    for name in ("crown.prr", "crown.csv"):
        prof = get_profile(str(tmp_path / name))
        assert prof.body == "rail" and abs(float(prof.z(10.0)) + 100.0 / 600.0) < 1e-6


@pytest.mark.parametrize("path,fragment", _expected("bad_scenes_generated"),
                         ids=[p.stem for p, _ in _expected("bad_scenes_generated")])
def test_bad_scene(path, fragment, tmp_path, capsys):
    from contact.__main__ import main

    out = tmp_path / "out"
    rc = main(["simulate", str(path), "--out", str(out)])
    _check(rc, capsys.readouterr(), path, fragment, out)


@pytest.mark.parametrize("path,fragment", _expected("bad_wheel_rail_scenes"),
                         ids=[p.stem for p, _ in _expected("bad_wheel_rail_scenes")])
def test_bad_wheel_rail_scene(path, fragment, tmp_path, capsys):
    from contact.__main__ import main

    out = tmp_path / "out"
    rc = main(["simulate", str(path), "--out", str(out)])
    _check(rc, capsys.readouterr(), path, fragment, out)


@pytest.mark.parametrize("path,fragment", _expected("bad_calibration_configs_generated"),
                         ids=[p.stem for p, _ in _expected("bad_calibration_configs_generated")])
def test_bad_calibration_config(path, fragment, tmp_path, capsys):
    from calibration.__main__ import main

    out = tmp_path / "out"
    rc = main(["run", str(path), "--out", str(out), "--quiet"])
    _check(rc, capsys.readouterr(), path, fragment, out)


@pytest.mark.parametrize("path,fragment", _expected("bad_profiles"),
                         ids=[p.name for p, _ in _expected("bad_profiles")])
def test_bad_profile_file(path, fragment, tmp_path, capsys):
    from meshes.__main__ import main

    out = tmp_path / "out"
    rc = main(["mesh", str(path), "--y0", "0", "--h-min", "2", "--h-max", "8", "--out", str(out / "m.vtu")])
    _check(rc, capsys.readouterr(), path, fragment, out)


@pytest.mark.parametrize("path,fragment", _expected("bad_layer_tables"),
                         ids=[p.name for p, _ in _expected("bad_layer_tables")])
def test_bad_layer_table(path, fragment, tmp_path, capsys):
    """Each broken table is used by a scene (layers.rail): the scene is refused, naming the table key."""
    from contact.__main__ import main

    scene = dict(make_corpus.SCENE)
    scene.pop("layers.combined")
    scene.pop("reference")
    make_corpus.write_toml(tmp_path / "uses_table.toml", scene, "uses a broken layer table")
    with open(tmp_path / "uses_table.toml", "a", encoding="utf-8") as fh:
        fh.write(f"\n[layers]\nrail = {json.dumps(str(path))}\nposition_mm = {{rail = 0.0}}\n")
    out = tmp_path / "out"
    rc = main(["simulate", str(tmp_path / "uses_table.toml"), "--out", str(out)])
    captured = capsys.readouterr()
    _check(rc, captured, path, fragment, out)
    assert "layers.rail" in captured.err


@pytest.mark.parametrize("h_min, h_max, key", [("1e-9", "5", "h_min"), ("0.0009", "5", "h_min"),
                                               ("0.01", "2000", "h_max")])
def test_absurd_mesh_sizes_are_refused_up_front(h_min, h_max, key, tmp_path, capsys):
    """An element size that would ask Gmsh for billions of elements is an input error (exit 2), not a run that
    ends in a numerical failure or out of memory."""
    from meshes.__main__ import main

    out = tmp_path / "out"
    rc = main(["mesh", "60E1", "--y0", "0", "--h-min", h_min, "--h-max", h_max, "--out", str(out / "m.vtu")])
    captured = capsys.readouterr()
    err = captured.err.strip()
    assert rc == 2 and err.startswith(f"error: {key}:") and "\n" not in err, err
    assert not out.exists()
