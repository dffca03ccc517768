"""A rolling run's output folder: built beside --out and published pass by pass into <out>.partial; --out keeps an
earlier output until the run ends (complete or stopped by a failed step), a killed run's passes stay in the
partial folder with their status, and a folder the tool did not write is refused before any FEM."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from calibration.rolling.config import (ContactSettings, RollingConfig, RollingRunSettings, TrackMeshSettings,
                                        TrackSettings)
from calibration.rolling.run import run_rolling
from wrlayer.errors import InputError, Terminated

ROOT = Path(__file__).resolve().parents[3]
ENV = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}


def config(passes: int, plots: bool = False) -> RollingConfig:
    """Frictionless EPP line contact at p0/k = 3.5 on a tiny 2D block (about 0.1 s a pass)."""
    return RollingConfig(contact=ContactSettings(a_mm=1.0, levels=(3.5,), model="2d", level_unit="k"),
                         track=TrackSettings(length_factor=1.0, step_factor=1.0, n_passes=passes, ramp_steps=1),
                         mesh=TrackMeshSettings(elements_per_semi_axis=2.0, size_factor=4.0),
                         run=RollingRunSettings(plots=plots, linear_solver="scipy"))


def files_of(folder: Path) -> dict[str, bytes]:
    return {str(p.relative_to(folder)): p.read_bytes() for p in folder.rglob("*") if p.is_file()}


def test_a_complete_run_replaces_the_earlier_output_whole(tmp_path):
    out = tmp_path / "out"
    first = run_rolling(config(2, plots=True), out)
    assert (out / "fields" / "level_0" / "passes.pvd").is_file() and first.status == "complete"
    (out / "notes.txt").write_text("mine")
    second = run_rolling(config(1), out)
    data = json.loads((out / "rolling.json").read_text())
    assert data["status"] == "complete" and len(data["levels"][0]["groove_mm"]) == 1
    assert not (out / "fields").exists()                    # the earlier run's fields are not mixed in
    assert (out / "notes.txt").read_text() == "mine"        # a user's file is carried over
    assert second.files == [str(out / "rolling.json")]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]   # no partial, staging or lock left
    assert [Path(f) for f in first.files] == [out / "rolling.json", out / "fields" / "level_0" / "passes.pvd"]


def test_a_killed_run_keeps_the_earlier_output_and_its_passes_in_the_partial_folder(tmp_path):
    out = tmp_path / "out"
    run_rolling(config(1), out)
    before = files_of(out)

    def stop_after_two(text):
        if "pass 2" in text:
            raise Terminated()

    with pytest.raises(Terminated):
        run_rolling(config(5, plots=True), out, progress=stop_after_two)
    assert files_of(out) == before
    partial = json.loads((tmp_path / "out.partial" / "rolling.json").read_text())
    assert partial["status"] == "terminated (SIGTERM) after 2 pass(es)"
    assert len(partial["levels"][0]["groove_mm"]) == 2
    assert (tmp_path / "out.partial" / "fields" / "level_0" / "passes.pvd").is_file()
    run_rolling(config(1), out)                              # the next complete run removes the partial folder
    assert not (tmp_path / "out.partial").exists()


def test_a_folder_the_tool_did_not_write_is_refused_before_any_fem(tmp_path, monkeypatch):
    import calibration.rolling.run as run_module

    out = tmp_path / "mine"
    out.mkdir()
    (out / "thesis.tex").write_text("x")
    monkeypatch.setattr(run_module, "build_model", lambda *a: pytest.fail("FEM started"))
    with pytest.raises(InputError, match="not an output folder of this tool"):
        run_rolling(config(1), out)
    assert files_of(out) == {"thesis.tex": b"x"}


def test_sigterm_says_what_was_kept(tmp_path):
    """``wrlayer rolling`` sent SIGTERM after a few passes: exit 143, one line naming the partial folder and that
    --out keeps the earlier output, which is unchanged."""
    cfg = tmp_path / "tiny.toml"
    text = ('[contact]\nmodel = "2d"\na_mm = 1.0\nlevels = {levels}\nlevel_unit = "k"\n'
            "[track]\nlength_factor = 1.0\nstep_factor = 1.0\nn_passes = {passes}\nramp_steps = 1\n"
            "[mesh]\nelements_per_semi_axis = 2\nsize_factor = 4\n"
            '[run]\nplots = true\nlinear_solver = "scipy"\n')
    out = tmp_path / "out"
    command = [sys.executable, "-m", "calibration", "rolling", str(cfg), "--out", str(out), "--quiet", "--force"]
    cfg.write_text(text.replace("{passes}", "1").replace("{levels}", "[3.5]"))
    assert subprocess.run(command, env=ENV, cwd=ROOT, capture_output=True, timeout=300).returncode == 0
    before = files_of(out)
    levels = str([3.5 + 0.05 * k for k in range(10)])
    cfg.write_text(text.replace("{passes}", "50").replace("{levels}", levels))    # 500 passes: tens of seconds
    run = subprocess.Popen(command, env=ENV, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and not (tmp_path / "out.partial" / "rolling.json").is_file():
        time.sleep(0.05)
    run.send_signal(signal.SIGTERM)
    assert run.wait(timeout=60) == 143
    line = run.stderr.read().strip()
    assert line.startswith("error: terminated (SIGTERM); ") and line.count("\n") == 0, line
    assert f"completed pass(es) kept in {tmp_path / 'out.partial'}; {out} keeps the earlier output" in line, line
    assert files_of(out) == before
    status = json.loads((tmp_path / "out.partial" / "rolling.json").read_text())["status"]
    assert status.startswith("terminated (SIGTERM) after "), status
    assert not list(tmp_path.glob(".out.*"))
