"""--version and help texts of every entry point, and the ``wrlayer`` console command's dispatch."""

import subprocess
import sys

import pytest

from wrlayer import cli
from wrlayer.progress import progress, progress_enabled
from wrlayer.version import code_version, version_text

ENTRY_POINTS = ["contact", "calibration", "meshes", "benchmarks", "benchmarks.stress"]


@pytest.mark.parametrize("module", ENTRY_POINTS)
def test_version_names_package_and_revision(module):
    run = subprocess.run([sys.executable, "-m", module, "--version"], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    line = run.stdout.strip()
    assert line.startswith(f"python -m {module} ")
    assert code_version() in line                      # the code revision, e.g. "git 0b546d5"


@pytest.mark.parametrize("argv", [["contact", "simulate"], ["contact", "simulate-all"], ["contact", "wear"],
                                  ["calibration", "run"],
                                  ["meshes", "mesh"], ["meshes", "plots"]])
def test_every_help_has_an_example_and_the_exit_codes(argv):
    run = subprocess.run([sys.executable, "-m", *argv, "--help"], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0
    command = cli.wrlayer_name(argv[1])                 # usage and examples in the console command's form
    assert run.stdout.startswith(f"usage: wrlayer {command} ")
    assert f"examples:\n  wrlayer {command} " in run.stdout
    assert "\nreference: docs/" in run.stdout
    for code in cli.EXIT_CODES:
        assert f"\n  {code:>3}  " in run.stdout


def test_wrlayer_command_dispatches(tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        cli.main(["--version"])
    assert exc.value.code == 0
    assert capsys.readouterr().out.strip() == version_text("wrlayer")
    # a bad scene path through the console command: the contact entry point's one-line error and exit code 2
    rc = cli.main(["simulate", str(tmp_path / "missing.toml"), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert rc == 2 and err.startswith("error: ") and err.count("\n") == 1
    assert not (tmp_path / "o").exists()


def test_wrlayer_unknown_command_is_a_usage_error(capsys):
    with pytest.raises(SystemExit) as exc:
        cli.main(["frobnicate"])
    assert exc.value.code == 2
    assert "invalid choice" in capsys.readouterr().err


def test_progress_bar_only_on_a_terminal(monkeypatch):
    monkeypatch.delenv("WRLAYER_PROGRESS", raising=False)
    items = [1, 2, 3]
    # pytest captures stderr: not a terminal, so no bar (no escape codes in logs; one line per item instead)
    assert not progress_enabled() and list(progress(items, desc="x")) == items
    monkeypatch.setenv("WRLAYER_PROGRESS", "1")
    assert progress_enabled() and list(progress(items, desc="x")) == items
    assert not progress_enabled(quiet=True)


def test_installed_version_printed_once(monkeypatch):
    import wrlayer.version as version

    monkeypatch.setattr(version, "code_version", lambda: "wrlayer 0.1.0")
    monkeypatch.setattr(version, "package_version", lambda: "0.1.0")
    assert version.version_text("wrlayer") == "wrlayer 0.1.0"
    monkeypatch.setattr(version, "code_version", lambda: "git v0.1.0-3-gabc1234")
    assert version.version_text("wrlayer") == "wrlayer 0.1.0 (git v0.1.0-3-gabc1234)"
