"""Faults of a calibration run: a killed run leaves no worker behind (nor the caller's pipes held open), a
cache entry that is valid JSON but wrong (or a folder) is recomputed, one that is a FIFO, a link to /dev/zero, a
link loop, oversize or unreadable is a miss with a warning (never a hang or out of memory), two runs into one --out cannot mix, a warm rerun notices
a CSV that does not belong to its JSON table. Each with a real run (coarse settings, seconds)."""

import contextlib
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from calibration.__main__ import main
from calibration.config import load_config
import calibration.pipeline as pipeline
from calibration.cache import load_indentation
from calibration.pipeline import run_calibration
from calibration.tasks import PositionOutcome
from wrlayer.layer_table import LayerTable
from wrlayer.atomic_write import output_lock

ROOT = Path(__file__).resolve().parents[2]
COARSE = ROOT / "calibration" / "configs" / "test_coarse.toml"


def _quiet(*args, **kw):
    pass


@pytest.fixture(scope="module")
def warm(tmp_path_factory):
    """A finished coarse run (one rail position) to corrupt in the tests (each test copies it)."""
    out = tmp_path_factory.mktemp("warm") / "out"
    run_calibration(load_config(COARSE), out, show_progress=False, log=_quiet)
    return out


def _copy(warm: Path, tmp_path: Path) -> Path:
    out = tmp_path / "out"
    shutil.copytree(warm, out)
    return out


@pytest.mark.parametrize("kind", ["{}", "folder"])
def test_wrong_fem_cache_entry_is_recomputed(warm, tmp_path, monkeypatch, kind):
    """An unusable FEM entry (the schema's cases: tests/calibration/test_cache.py) is recomputed and rewritten.
    The FEM here returns the warm run's result: what is tested is the pipeline's handling, not the FEM."""
    out = _copy(warm, tmp_path)
    (entry,) = [p for p in (out / "cache").glob("*.json") if not p.name.startswith("fit-")]
    good = load_indentation(entry)[0]
    entry.unlink()
    if kind == "folder":
        (entry / "inside").mkdir(parents=True)
    else:
        entry.write_text(kind)
    for fit in (out / "cache").glob("fit-*.json"):
        fit.unlink()
    monkeypatch.setattr(pipeline, "run_position", lambda task: PositionOutcome(task.key, good))
    logged = []
    summary = run_calibration(load_config(COARSE), out, show_progress=False, log=logged.append)
    assert summary["failed"] == [] and summary["positions_computed"] == 1 and summary["positions_cached"] == 0
    assert any("invalid" in line and entry.name in line for line in logged), logged
    assert load_indentation(entry)[0] == good  # rewritten with a valid entry
    LayerTable.read(out / "rail_layer_table.json")


def test_wrong_fit_cache_entry_is_refitted(warm, tmp_path):
    out = _copy(warm, tmp_path)
    (fit,) = list((out / "cache").glob("fit-*.json"))
    before = json.loads(fit.read_text())
    fit.write_text("{}")
    summary = run_calibration(load_config(COARSE), out, show_progress=False, log=_quiet)
    assert summary["failed"] == [] and summary["positions_cached"] == 1
    assert json.loads(fit.read_text())["characteristic"] == before["characteristic"]


def test_csv_of_another_run_is_noticed_by_a_warm_rerun(warm, tmp_path):
    out = _copy(warm, tmp_path)
    csv = out / "rail_layer_table.csv"
    good = csv.read_text()
    csv.write_text(good.replace("60E1", "54E1"))  # the CSV of another run beside this JSON table
    run_calibration(load_config(COARSE), out, show_progress=False, log=_quiet)
    assert csv.read_text() == good == LayerTable.read(out / "rail_layer_table.json").to_csv()


def test_second_run_into_a_busy_out_is_refused(warm, tmp_path, capsys):
    """A run holds the --out lock (here: another process): a second run exits 2 with one line, writes nothing."""
    out = _copy(warm, tmp_path)
    holder = subprocess.Popen([sys.executable, "-c", "import sys, time; from wrlayer.atomic_write import "
                               "output_lock\nwith output_lock(sys.argv[1]):\n print('locked', flush=True); "
                               "time.sleep(60)", str(out)], stdout=subprocess.PIPE, text=True,
                              env={**os.environ, "PYTHONPATH": str(ROOT)})
    try:
        assert holder.stdout.readline().strip() == "locked"
        before = {p: p.stat().st_mtime_ns for p in out.rglob("*")}
        rc = main(["run", str(COARSE), "--out", str(out), "--quiet"])
        err = capsys.readouterr().err.strip()
        assert rc == 2 and "\n" not in err and f"pid {holder.pid}" in err and "another run" in err, err
        assert {p: p.stat().st_mtime_ns for p in out.rglob("*")} == before
    finally:
        holder.kill()
        holder.wait()
    with output_lock(out):  # released by the killed holder
        pass


def _children(pid: int) -> set[int]:
    kids = set()
    for task in Path(f"/proc/{pid}/task").glob("*"):
        try:
            kids |= {int(x) for x in (task / "children").read_text().split()}
        except OSError:
            pass
    return kids


def _alive(pid: int) -> bool:
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return False
    return "zombie" not in status.lower()


@pytest.mark.slow
def test_sigterm_after_an_in_process_fem_says_what_was_cached(tmp_path):
    """SIGTERM to a one-worker run (its FEM, and so Gmsh, in the run's own process) once a position is cached: exit
    143 and the one line naming the cache, not a bare death by the signal: Gmsh's start had reset SIGTERM to its
    default behind Python's handler (meshes.meshing.gmsh_session.signal_dispositions_kept)."""
    cfg = tmp_path / "four.toml"
    cfg.write_text(COARSE.read_text().replace("positions_mm = [0.0]", "positions_mm = [0.0, 5.0, 10.0, 15.0]"))
    out = tmp_path / "out"
    proc = subprocess.Popen([sys.executable, "-m", "calibration", "run", str(cfg), "--out", str(out), "--quiet"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, cwd=ROOT,
                            env={**os.environ, "PYTHONPATH": str(ROOT)})
    deadline = time.monotonic() + 120
    while proc.poll() is None and time.monotonic() < deadline and not list((out / "cache").glob("*.json")):
        time.sleep(0.05)
    proc.send_signal(signal.SIGTERM)
    rc, err = proc.wait(timeout=60), proc.stderr.read()
    assert rc == 143, (rc, err)
    cached = list((out / "cache").glob("*.json"))
    assert err.strip() == (f"error: terminated (SIGTERM); {len(cached)} computed position(s) cached in "
                           f"{out / 'cache'} (a rerun reuses them)"), err
    assert cached and all(load_indentation(p)[0] is not None for p in cached)


@pytest.mark.skipif(not Path("/proc/self/task").is_dir(), reason="needs Linux /proc")
@pytest.mark.slow
def test_killed_run_leaves_no_workers_and_frees_the_pipes(tmp_path):
    """kill -9 of a run with 2 workers while they compute: the workers (and the resource tracker) end, the
    caller's pipes reach end-of-file at once (nothing keeps them open), the next run into the folder works."""
    cfg = tmp_path / "three.toml"
    cfg.write_text(COARSE.read_text().replace("positions_mm = [0.0]", "positions_mm = [0.0, 5.0, 10.0]")
                   .replace("workers = 1", "workers = 2"))
    out = tmp_path / "out"
    proc = subprocess.Popen([sys.executable, "-m", "calibration", "run", str(cfg), "--out", str(out), "--quiet"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, start_new_session=True, cwd=ROOT,
                            env={**os.environ, "PYTHONPATH": str(ROOT)})
    kids: set[int] = set()
    t0 = time.monotonic()
    while time.monotonic() - t0 < 120 and len(kids) < 3:  # 2 workers + the resource tracker
        kids = _children(proc.pid)
        time.sleep(0.2)
    assert len(kids) >= 3, kids
    time.sleep(1.0)
    os.kill(proc.pid, signal.SIGKILL)
    proc.communicate(timeout=30)  # TimeoutExpired here = a leftover process holds the pipes open
    deadline = time.monotonic() + 15
    while time.monotonic() < deadline and any(_alive(k) for k in kids):
        time.sleep(0.2)
    assert not [k for k in kids if _alive(k)]
    assert main(["run", str(COARSE), "--out", str(out), "--quiet"]) == 0


def test_costly_calibration_is_refused_with_the_estimate(tmp_path, capsys):
    """A 3D configuration with a fine mesh: refused before any FEM (exit 2, the estimate, --force named), nothing
    written."""
    cfg = tmp_path / "costly.toml"
    text = re.sub(r"elements_per_semi_axis = [0-9.]+", "elements_per_semi_axis = 60", COARSE.read_text())
    cfg.write_text(re.sub(r'model = "[23]d"', 'model = "3d"', text))
    out = tmp_path / "out"
    rc = main(["run", str(cfg), "--out", str(out), "--quiet"])
    err = capsys.readouterr().err.strip()
    assert rc == 2 and "\n" not in err and not out.exists()
    assert "estimated cost 1 3D FEM position(s) on 1 worker(s) ~ " in err and "--force" in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["costly.toml"]


# ------------------------------------------------------------------------------------------------ hostile entries
#: Seconds a hostile cache entry may take before the test calls it a hang (the old reader blocked on a FIFO).
HANG_S = 20


@contextlib.contextmanager
def _no_hang(seconds: int = HANG_S):
    """Fail (instead of hanging the test run) when the block takes more than ``seconds``."""
    def alarm(signum, frame):
        raise TimeoutError(f"hung for {seconds} s")

    previous = signal.signal(signal.SIGALRM, alarm)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)


def _hostile(kind: str, path: Path, monkeypatch) -> str:
    """Put an entry of ``kind`` at ``path``; returns the words the warning must hold."""
    path.unlink()
    if kind == "fifo":
        os.mkfifo(path)
        return "a FIFO (named pipe), not a regular file"
    if kind == "dev-zero":
        path.symlink_to("/dev/zero")
        return "a character device, not a regular file"
    if kind == "link-loop":
        path.symlink_to(path.name)
        return "a symbolic-link loop"
    if kind == "oversize":  # sparse: no disk used
        from wrlayer.input_files import MAX_DATA_BYTES

        with open(path, "wb") as fh:
            fh.truncate(MAX_DATA_BYTES + 1)
        return f"{MAX_DATA_BYTES + 1} bytes, more than the {MAX_DATA_BYTES} accepted"
    if kind == "unreadable":  # chmod 000 does not stop root: the open itself fails as it would for another user
        import wrlayer.input_files as input_files

        real_open = os.open

        def denied(name, *args, **kw):
            if Path(name) == path:
                raise PermissionError(13, "Permission denied", str(name))
            return real_open(name, *args, **kw)

        path.write_text("{}")
        monkeypatch.setattr(input_files.os, "open", denied)
        return "cannot read (Permission denied)"
    raise ValueError(kind)


HOSTILE = ["fifo", "dev-zero", "link-loop", "oversize", "unreadable"]


@pytest.mark.parametrize("kind", HOSTILE)
def test_hostile_fem_cache_entry_is_a_miss(warm, tmp_path, monkeypatch, kind):
    """A FEM cache entry that is a FIFO, a link to /dev/zero, a link loop, oversize or unreadable: a cache miss
    with a warning naming why, recomputed and replaced by a regular entry; never a hang or out of memory."""
    out = _copy(warm, tmp_path)
    (entry,) = [p for p in (out / "cache").glob("*.json") if not p.name.startswith("fit-")]
    good = load_indentation(entry)[0]
    why = _hostile(kind, entry, monkeypatch)
    monkeypatch.setattr(pipeline, "run_position", lambda task: PositionOutcome(task.key, good))
    logged = []
    with _no_hang():
        summary = run_calibration(load_config(COARSE), out, show_progress=False, log=logged.append)
    assert summary["failed"] == [] and summary["positions_computed"] == 1 and summary["positions_cached"] == 0
    assert any(f"{entry.name} of " in line and why in line and "recomputing" in line for line in logged), logged
    monkeypatch.undo()
    assert entry.is_file() and not entry.is_symlink() and load_indentation(entry)[0] == good


@pytest.mark.parametrize("kind", HOSTILE)
def test_hostile_fit_cache_entry_is_a_miss(warm, tmp_path, monkeypatch, kind):
    """The same for a fit entry: refitted (same characteristic), with a warning, the entry replaced."""
    out = _copy(warm, tmp_path)
    (fit,) = list((out / "cache").glob("fit-*.json"))
    before = json.loads(fit.read_text())
    why = _hostile(kind, fit, monkeypatch)
    logged = []
    with _no_hang():
        summary = run_calibration(load_config(COARSE), out, show_progress=False, log=logged.append)
    assert summary["failed"] == [] and summary["positions_cached"] == 1
    assert any(f"{fit.name} of " in line and why in line and "recomputing" in line for line in logged), logged
    monkeypatch.undo()
    assert fit.is_file() and not fit.is_symlink()
    assert json.loads(fit.read_text())["characteristic"] == before["characteristic"]
