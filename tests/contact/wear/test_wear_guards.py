"""Bounds and guards of a wear run (refused before anything is written, one line, exit code 2) and how its output
folder is published: an earlier run kept until a step completes, a user's files kept, a full disk named."""

import errno
import json
import os

import pytest

from contact.__main__ import main
from contact.wear import outputs
from contact.wear.cost import wear_cost
from contact.wear.scene import parse_wear_scene

FAST = {"distance_km": 40.0, "steps": 2, "inelastic": False}


def _refused(tmp_path, capsys, scene_file, *args):
    out = tmp_path / "out"
    assert main(["wear", str(scene_file), "--out", str(out), "--quiet", *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error: "), err
    assert not out.exists() and not list(tmp_path.glob(".out.*"))
    return err[0]


@pytest.mark.parametrize("over, fragment", [
    ({"wear": {"steps": 1_000_000_000}}, "wear.steps: must be <= 1000"),
    ({"wear": {"smoothing_mm": 1e6}}, "wear.smoothing_mm: must be <= 1000 x grid_mm = 200 mm"),
    ({"collective": {"lateral_mm": {"start": 0.0, "stop": 5.0, "step": 1e-4}, "yaw_rad": 0.0,
                     "weights": "uniform"}}, "collective.lateral_mm: at most 10000 conditions, got 50001"),
    ({"wear": {"scheduler": "tls://"}}, "wear.scheduler: 'tls://' is not a scheduler address"),
    ({"wear": {"scheduler": "http://host:8786"}}, "wear.scheduler: 'http://host:8786': unknown scheme 'http'"),
    ({"wear": {"scheduler": "tcp://host:0"}}, "wear.scheduler: 'tcp://host:0': the port must be"),
    ({"wear": {"steps": 1000}, "collective": {"lateral_mm": {"start": -2.0, "stop": 2.0, "step": 0.04},
                                              "yaw_rad": 0.0, "weights": "uniform"}},
     "estimated cost 1000 steps x 101 conditions"),
])
def test_refused_before_anything_is_written(tmp_path, capsys, wear_dict, write_scene, over, fragment):
    data = wear_dict(layers=None, wear=FAST)
    for key, value in over.items():
        data[key] = {**data[key], **value} if key == "wear" else {**value}
    err = _refused(tmp_path, capsys, write_scene(data))
    assert fragment in err, err


def test_scheduler_option_checked_before_anything(tmp_path, capsys, wear_dict, write_scene):
    err = _refused(tmp_path, capsys, write_scene(wear_dict(layers=None, wear=FAST)), "--scheduler", "ucx://h:x")
    assert err == "error: --scheduler: 'ucx://h:x': the port must be an integer 1..65535, got 'x'"


def test_cost_estimate_of_the_example_is_seconds(tmp_path):
    import tomllib
    from pathlib import Path

    path = Path(__file__).resolve().parents[3] / "scenes" / "wear" / "s1002_60e1.toml"
    est = wear_cost(parse_wear_scene(tomllib.loads(path.read_text()), path))
    assert est.factors["steps"] == 3 and est.factors["conditions"] == 7 and est.factors["sides"] == 2
    assert 5.0 < est.seconds < 90.0  # measured about 30 s in-process


def test_recalibration_template_not_utf8_or_a_loop(tmp_path, capsys, wear_dict, write_scene):
    latin = tmp_path / "recal.toml"
    latin.write_bytes("# Kalibrierung f\u00fcr R\u00e4der\n[run]\nworkers = 1\n".encode("latin-1"))
    scene = write_scene(wear_dict(wear={**FAST, "recalibrate": {"config": str(latin)}}))
    err = _refused(tmp_path, capsys, scene)
    assert err.startswith("error: w.toml: wear.recalibrate.config (recal.toml): not UTF-8 text"), err
    (tmp_path / "a.toml").symlink_to(tmp_path / "b.toml")
    (tmp_path / "b.toml").symlink_to(tmp_path / "a.toml")
    scene = write_scene(wear_dict(wear={**FAST, "recalibrate": {"config": str(tmp_path / "a.toml")}}))
    assert "symbolic-link loop" in _refused(tmp_path, capsys, scene)


def test_layer_table_a_loop_or_a_fifo(tmp_path, capsys, wear_dict, write_scene):
    (tmp_path / "a.json").symlink_to(tmp_path / "b.json")
    (tmp_path / "b.json").symlink_to(tmp_path / "a.json")
    os.mkfifo(tmp_path / "fifo.json")
    for name, fragment in (("a.json", "symbolic-link loop"), ("fifo.json", "a FIFO (named pipe)")):
        data = wear_dict(wear=FAST)
        data["layers"] = {**data["layers"], "rail": str(tmp_path / name)}
        err = _refused(tmp_path, capsys, write_scene(data))
        assert "layers.rail" in err and fragment in err, err


def test_earlier_run_and_user_files_kept_until_replaced(tmp_path, capsys, wear_dict, write_scene, monkeypatch):
    """A run that fails before its first step leaves the earlier complete run as it was; a user's file in --out
    survives a run; a full disk during step 2 names the path, leaves step 1 published beside --out (marked) and the
    earlier run in --out."""
    scene = write_scene(wear_dict(layers=None, wear=FAST))
    out = tmp_path / "out"
    assert main(["wear", str(scene), "--out", str(out), "--quiet", "--no-plots"]) == 0
    (out / "notes.txt").write_text("mine")
    before = {p: p.read_bytes() for p in out.rglob("*") if p.is_file()}

    def no_space(*args, **kwargs):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(outputs, "write_step", no_space)
    capsys.readouterr()
    assert main(["wear", str(scene), "--out", str(out), "--quiet", "--no-plots"]) == 2
    assert capsys.readouterr().err.strip() == f"error: {out}: no space left on device"
    assert {p: p.read_bytes() for p in out.rglob("*") if p.is_file()} == before
    assert not list(tmp_path.glob(".out.*"))

    real, calls = outputs.write_table, []

    def full_on_step_2(out_dir, run):
        calls.append(1)
        if len(calls) == 2:
            raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC), str(out_dir / "steps.csv"))
        return real(out_dir, run)

    monkeypatch.undo()
    monkeypatch.setattr(outputs, "write_table", full_on_step_2)
    assert main(["wear", str(scene), "--out", str(out), "--quiet", "--no-plots"]) == 2
    err = capsys.readouterr().err.strip()
    assert err.endswith("steps.csv: no space left on device") and err.count("\n") == 0, err
    res = json.loads((tmp_path / "out.partial" / "result.json").read_text())  # step 1 beside --out, marked
    assert len(res["steps"]) == 1 and res["status"].startswith("stopped after step 1: ")
    assert {p: p.read_bytes() for p in out.rglob("*") if p.is_file()} == before  # the earlier run as it was
    assert not list(tmp_path.glob(".out.*"))


def test_sigterm_while_the_run_ends_marks_the_published_steps(tmp_path, capsys, wear_dict, write_scene,
                                                               monkeypatch):
    """SIGTERM after the last step, while the final files and pictures are written: the published steps are
    marked "terminated (SIGTERM) after step 2" (they stayed "running" before), the line says where they are, and
    --out keeps the earlier run."""
    import signal

    import contact.run_files as run_files

    scene = write_scene(wear_dict(layers=None, wear=FAST))
    out, partial = tmp_path / "out", tmp_path / "out.partial"
    assert main(["wear", str(scene), "--out", str(out), "--quiet", "--no-plots"]) == 0
    before = {p: p.read_bytes() for p in out.rglob("*") if p.is_file()}

    def killed_while_drawing(run, out_dir, plots):
        os.kill(os.getpid(), signal.SIGTERM)
        return []

    monkeypatch.setattr(run_files, "_wear_pictures", killed_while_drawing)
    capsys.readouterr()
    assert main(["wear", str(scene), "--out", str(out), "--quiet"]) == 143
    assert capsys.readouterr().err.strip() == (f"error: terminated (SIGTERM); 2 completed step(s) kept in {partial}; "
                                               f"{out} keeps the earlier output")
    assert json.loads((partial / "result.json").read_text())["status"] == "terminated (SIGTERM) after step 2"
    assert {p: p.read_bytes() for p in out.rglob("*") if p.is_file()} == before
    assert not list(tmp_path.glob(".out*.*"))
