"""A wheel–rail sweep with failed cases: exit code 4, the failed cases (case, wheel, reason) on stderr, every result
written."""

import json

import pytest

from contact.__main__ import main


def _write(path, sweep):
    path.write_text('type = "wheel_rail"\n[wheel]\nside = "right"\n[sweep]\nlateral_mm = ' + repr(sweep) + "\n",
                    encoding="utf-8")
    return path


def test_failed_case_exits_4_and_names_case_and_wheel(tmp_path, capsys):
    scene = _write(tmp_path / "s.toml", [0.0, 25.0])
    out = tmp_path / "out"
    assert main(["simulate", str(scene), "--out", str(out)]) == 4
    err = capsys.readouterr().err
    lines = [ln for ln in err.splitlines() if ln.startswith("error: s.toml: case 1: right: ")]
    assert len(lines) == 1 and "flange through the rail" in lines[0]
    assert "1 of 2 cases failed" in err
    result = json.loads((out / "result.json").read_text())
    assert result["n_failed"] == 1 and result["cases"][1]["failed_wheel"] == "right"
    assert "wheels" in result["cases"][0] and (out / "cases.csv").is_file()


def test_a_sweep_without_failures_exits_0(tmp_path, capsys):
    scene = _write(tmp_path / "s.toml", [0.0])
    assert main(["simulate", str(scene), "--out", str(tmp_path / "out")]) == 0
    assert "failed" not in capsys.readouterr().err


def test_exit_code_4_is_documented():
    from wrlayer.cli import EXIT_CODES

    assert "wheel-rail sweep" in EXIT_CODES[4]
    with pytest.raises(SystemExit):
        main(["--help"])
