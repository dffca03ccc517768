"""The corpus of broken scene files (tests/inputs/bad_scenes): each gives ONE line ``error: ...`` naming the field
(the first line of each file says ``# expect: <text the message must contain>``), a non-zero exit code, no
traceback and no output file."""

import subprocess
import sys
from pathlib import Path

import pytest

from contact.__main__ import main

BAD = Path(__file__).resolve().parents[2] / "inputs" / "bad_scenes"
FILES = sorted(BAD.glob("*.toml"))


def expected_text(path: Path) -> str:
    first = path.read_text(encoding="utf-8").splitlines()[0]
    assert first.startswith("# expect: "), f"{path.name} must start with '# expect: <field>'"
    return first.removeprefix("# expect: ").strip()


def test_corpus_is_there():
    assert len(FILES) >= 30


@pytest.mark.parametrize("path", FILES, ids=[p.stem for p in FILES])
def test_bad_scene_gives_one_line_error(path, tmp_path, capsys):
    out = tmp_path / "out"
    rc = main(["simulate", str(path), "--out", str(out), "--json"])
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert rc != 0
    assert len(lines) == 1, captured.err
    assert lines[0].startswith("error: ")
    assert expected_text(path) in lines[0]
    assert "Traceback" not in captured.err
    assert captured.out == ""
    assert not out.exists() or not any(out.iterdir())


def test_bad_scene_through_the_real_command_line(tmp_path):
    """One broken scene through ``python -m contact``: exit code 2 (bad input), one line, nothing written."""
    path = BAD / "negative_force.toml"
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, "-m", "contact", "simulate", str(path), "--out", str(out)],
                          capture_output=True, text=True, timeout=120, check=False)
    assert proc.returncode == 2
    assert proc.stderr.strip() == "error: negative_force.toml: load.normal_force_N: must be >= 0.001, got -5"
    assert not out.exists()


def test_missing_scene_file(tmp_path, capsys):
    rc = main(["simulate", str(tmp_path / "nothing.toml"), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert rc == 2 and "nothing.toml" in err and "no such file" in err
