"""The ``wrlayer`` console command around the solvers: help texts in the ``wrlayer`` form naming the reference
pages, a lazy ``--version``, ``wrlayer example`` (shipped scenes and configurations copied out), the shared
reference folder's resolution and the numba cache of an installed package."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from wrlayer import cli, input_files, shipped, version
from wrlayer.errors import InputError

REPO = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("command", sorted(cli.COMMANDS))
def test_every_command_help_is_in_wrlayer_form_and_names_existing_reference_pages(command, capsys):
    with pytest.raises(SystemExit) as exc:
        cli.main([command, "--help"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    assert out.startswith(f"usage: wrlayer {command} ")
    assert f"examples:\n  wrlayer {command}" in out and "python -m" not in out
    pages = [line for line in out.splitlines() if line.startswith("reference: ")]
    assert len(pages) == 1
    for page in pages[0].removeprefix("reference: ").split(", "):
        assert (REPO / page).is_file(), page


@pytest.mark.parametrize("command", ["simulate", "simulate-all", "wear", "calibrate", "rolling", "mesh", "geometry"])
def test_every_command_that_reads_profile_files_takes_the_one_override_option(command, capsys):
    """--accept-unusual-profile, defined once (wrlayer.cli.add_profile_check_option), with one help text."""
    with pytest.raises(SystemExit):
        cli.main([command, "--help"])
    out = " ".join(capsys.readouterr().out.split())
    assert "--accept-unusual-profile read profile files without the plausibility checks" in out


def test_version_is_computed_only_when_asked(monkeypatch, capsys):
    def fail(prog):
        raise AssertionError("version_text called while building a parser")

    monkeypatch.setattr(cli, "version_text", fail)
    cli.parser("wrlayer", "d", ["wrlayer x"]).parse_args([])    # a run builds parsers without asking git
    monkeypatch.setattr(cli, "version_text", lambda prog: f"{prog} 9.9.9")
    with pytest.raises(SystemExit) as exc:
        cli.parser("wrlayer", "d", ["wrlayer x"]).parse_args(["--version"])
    assert exc.value.code == 0 and capsys.readouterr().out == "wrlayer 9.9.9\n"


def test_source_tree_version_is_pyprojects_and_the_tag_matches():
    text = (REPO / "pyproject.toml").read_text(encoding="utf-8")
    stated = text.split('\nversion = "', 1)[1].split('"', 1)[0]
    assert version.package_version() == stated
    assert version.software_versions()["wrlayer"] == stated          # what calibration tables record
    assert f"## {stated} - " in (REPO / "CHANGELOG.md").read_text(encoding="utf-8")


def test_installed_package_never_asks_git(monkeypatch):
    monkeypatch.setattr(version, "source_tree", lambda: None)
    monkeypatch.setattr(version, "package_version", lambda: "0.2.0")
    version.code_version.cache_clear()
    try:
        assert version.code_version() == "wrlayer 0.2.0"
        assert version.version_text("wrlayer") == "wrlayer 0.2.0"
    finally:
        version.code_version.cache_clear()


def test_example_list_names_scenes_configurations_scripts_and_what_runs_each(capsys):
    assert shipped.main(["--list"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert max(len(line) for line in lines) <= shipped.LIST_COLUMNS
    rows = {line.split()[0]: line.split()[1:4] for line in lines[1:]}
    assert rows["hertz_check"][:2] == ["wrlayer", "simulate"] and rows["wear/s1002_60e1"][:2] == ["wrlayer", "wear"]
    assert rows["config/test_coarse"][1] == "calibrate" and rows["config/rolling_halfspace"][1] == "rolling"
    assert rows["examples/ex02_hertz_check"][0] == "python"
    # the recalibration template is not offered as a scene to simulate
    assert rows["wear/recalibrate_similarity"] == ["template", "of", "wear/s1002_60e1_recalibrated"]
    assert set(rows) == {e.name for e in shipped.examples()}
    scenes = [n for n in rows if not n.startswith(("config/", "examples/"))]
    assert len(scenes) == len(list((REPO / "scenes").rglob("*.toml")))
    assert len([n for n in rows if n.startswith("examples/")]) == len(list((REPO / "examples").glob("ex*.py")))


def test_example_script_is_copied_alone_and_finds_its_scene_through_the_package(tmp_path, capsys):
    assert shipped.main(["examples/ex02_hertz_check", str(tmp_path)]) == 0
    assert f"run it: python {tmp_path / 'ex02_hertz_check.py'}" in capsys.readouterr().out
    text = (tmp_path / "ex02_hertz_check.py").read_text(encoding="utf-8")
    assert "scenes_dir()" in text and "parents[1]" not in text


def test_example_copies_a_scene_with_its_tables_and_never_overwrites(tmp_path, capsys):
    work = tmp_path / "work"
    assert shipped.main(["wear/s1002_60e1", str(work)]) == 0
    out = capsys.readouterr().out
    copied = sorted(p.relative_to(work).as_posix() for p in work.rglob("*") if p.is_file())
    assert copied == ["tables/rail_60E1_default.json", "tables/wheel_S1002_default.json", "wear/s1002_60e1.toml"]
    for rel in copied:
        assert (work / rel).read_bytes() == (REPO / "scenes" / rel).read_bytes()
    assert f"run it: wrlayer wear {work / 'wear' / 's1002_60e1.toml'} --out " in out
    # a second scene naming the same tables: the identical tables are kept, the scene is added
    assert shipped.main(["calibrated_layers", str(work)]) == 0
    assert (work / "calibrated_layers.toml").is_file()
    # a changed file is never overwritten: exit 2, one line, nothing written
    (work / "tables" / "rail_60E1_default.json").write_text("{}", encoding="utf-8")
    capsys.readouterr()
    assert shipped.main(["wear/s1002_60e1", str(work)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and err.count("\n") == 1 and "rail_60E1_default.json" in err
    assert (work / "tables" / "rail_60E1_default.json").read_text(encoding="utf-8") == "{}"


def test_example_configuration_and_reference_names(tmp_path, capsys):
    assert shipped.main(["config/test_coarse", str(tmp_path)]) == 0
    assert (tmp_path / "test_coarse.toml").read_bytes() == \
        (REPO / "calibration" / "configs" / "test_coarse.toml").read_bytes()
    assert "run it: wrlayer calibrate " in capsys.readouterr().out
    assert shipped.main(["manchester_a22", str(tmp_path)]) == 0
    assert "reference:mbench_a22_inputs.csv" in capsys.readouterr().out      # left in the reference folder
    assert shipped.main(["nope", str(tmp_path)]) == 2
    assert "wrlayer example --list" in capsys.readouterr().err


def test_copied_scene_runs_with_the_same_numbers(tmp_path):
    assert shipped.main(["hertz_check", str(tmp_path / "work")]) == 0
    results = []
    for scene, out in ((REPO / "scenes" / "hertz_check.toml", "orig"), (tmp_path / "work" / "hertz_check.toml", "copy")):
        assert cli.main(["simulate", str(scene), "--out", str(tmp_path / out), "--no-vtk"]) == 0
        results.append(json.loads((tmp_path / out / "result.json").read_text(encoding="utf-8"))["passes"][0])
    keys = ["length_mm", "width_mm", "area_mm2", "delta_mm", "p_max_MPa"]
    assert [results[0][k] for k in keys] == [results[1][k] for k in keys]


def test_missing_reference_file_names_both_places(tmp_path, monkeypatch):
    monkeypatch.setenv(input_files.REFERENCE_ENV, str(tmp_path))
    with pytest.raises(InputError) as err:
        input_files.resolve_reference("reference:none.csv", "s.toml: sweep.csv")
    text = str(err.value)
    assert f"$WRLAYER_REFERENCE = {tmp_path}" in text and "beside the repository" in text
    (tmp_path / "here.csv").write_text("x", encoding="utf-8")
    assert input_files.resolve_reference("reference:here.csv", "w") == tmp_path / "here.csv"
    monkeypatch.delenv(input_files.REFERENCE_ENV)
    assert input_files.reference_dir() == REPO.parent / "shared" / "reference"
    # an installed package: no folder beside a repository, the variable is the only way
    monkeypatch.setattr(input_files, "source_tree", lambda: None)
    assert input_files.reference_dir() is None
    with pytest.raises(InputError, match=r"\$WRLAYER_REFERENCE \(not set\); no folder beside the repository "
                                         r"\(an installed package\); set \$WRLAYER_REFERENCE"):
        input_files.resolve_reference("reference:profiles/a.prr", "s.toml: profiles.rail")


def test_installed_package_keeps_numba_cache_in_the_users_cache(tmp_path, monkeypatch):
    env = {"XDG_CACHE_HOME": str(tmp_path)}
    monkeypatch.setattr(os, "environ", env)                       # restored after the test
    cli.use_user_numba_cache()                                   # a source tree: numba's default
    assert "NUMBA_CACHE_DIR" not in env
    monkeypatch.setattr(cli, "source_tree", lambda: None)
    cli.use_user_numba_cache()
    assert env["NUMBA_CACHE_DIR"] == str(tmp_path / "wrlayer" / "numba")
    env["NUMBA_CACHE_DIR"] = "/elsewhere"                        # the user's choice wins
    cli.use_user_numba_cache()
    assert env["NUMBA_CACHE_DIR"] == "/elsewhere"


def test_command_line_module_imports_no_solver_library():
    code = ("import sys, contact.__main__, wrlayer.cli; contact.__main__.build_parser(); "
            "print(sorted({m.split('.')[0] for m in sys.modules} & {'numpy', 'scipy', 'numba', 'matplotlib', "
            "'meshio', 'concurrent'}))")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, cwd=REPO)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "[]"
