"""Output writing: user permissions, whole-folder replace, the output lock, stale staging folders; and real
contact runs that are killed or race into the same --out."""

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from wrlayer.atomic_write import (
    OutputError,
    atomic_output_dir,
    atomic_write_text,
    clean_stale_staging,
    output_lock,
    replace_output_dir,
    staged_output_dir,
)
from wrlayer.errors import InputError

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "scenes"
ENV = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg"}


@pytest.fixture
def umask_022():
    old = os.umask(0o022)
    yield
    os.umask(old)


def test_written_files_get_the_users_permissions(tmp_path, umask_022):
    path = atomic_write_text(tmp_path / "a.json", "{}")
    assert path.stat().st_mode & 0o777 == 0o644  # not tempfile's 0600
    with replace_output_dir(tmp_path / "out") as tmp:
        (tmp / "result.json").write_text("{}")
    assert (tmp_path / "out").stat().st_mode & 0o777 == 0o755
    with atomic_output_dir(tmp_path / "merged") as tmp:
        (tmp / "x.txt").write_text("x")
    assert (tmp_path / "merged").stat().st_mode & 0o777 == 0o755


def test_folder_is_replaced_as_a_whole_keeping_user_files(tmp_path):
    out = tmp_path / "out"
    with replace_output_dir(out) as tmp:
        (tmp / "result.json").write_text('{"run": 1}')
        (tmp / "old.png").write_bytes(b"png")
        (tmp / "deformed_profiles").mkdir()
        (tmp / "deformed_profiles" / "case000.prr").write_text("x")
    (out / "notes.txt").write_text("mine")
    with replace_output_dir(out) as tmp:
        (tmp / "result.json").write_text('{"run": 2}')
    assert sorted(p.name for p in out.rglob("*")) == ["notes.txt", "result.json"]
    assert json.loads((out / "result.json").read_text()) == {"run": 2}
    assert [p.name for p in tmp_path.iterdir()] == ["out"]  # no staging, old or lock file left


def test_failed_block_changes_nothing(tmp_path):
    out = tmp_path / "out"
    with replace_output_dir(out) as tmp:
        (tmp / "result.json").write_text("1")
    with pytest.raises(RuntimeError), replace_output_dir(out) as tmp:
        (tmp / "result.json").write_text("2")
        raise RuntimeError("solver failed")
    assert (out / "result.json").read_text() == "1"
    assert [p.name for p in tmp_path.iterdir()] == ["out"]


def test_a_folder_of_other_content_is_refused_not_deleted(tmp_path):
    out = tmp_path / "mine"
    out.mkdir()
    (out / "thesis.tex").write_text("years of work")
    with pytest.raises(InputError, match="other content"):
        with replace_output_dir(out) as tmp:
            (tmp / "result.json").write_text("{}")
    assert (out / "thesis.tex").read_text() == "years of work"


def _sleeper() -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])


def test_stale_staging_of_dead_runs_is_removed_live_ones_kept(tmp_path):
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    live = _sleeper()
    try:
        stale = tmp_path / f".out.staging-{dead.pid}-abc"
        old = tmp_path / f".out.old-{dead.pid}-def"
        busy = tmp_path / f".out.staging-{live.pid}-ghi"
        for d in (stale, old, busy):
            (d / "sub").mkdir(parents=True)
        assert set(clean_stale_staging(tmp_path / "out")) == {stale, old}
        assert busy.is_dir() and not stale.exists() and not old.exists()
    finally:
        live.kill()
        live.wait()


def test_lock_refuses_a_second_holder(tmp_path):
    holder = subprocess.Popen([sys.executable, "-c", "import sys, time; from wrlayer.atomic_write import "
                               "output_lock\nwith output_lock(sys.argv[1]):\n print('locked', flush=True); "
                               "time.sleep(60)", str(tmp_path / "out")], stdout=subprocess.PIPE, text=True, env=ENV)
    try:
        assert holder.stdout.readline().strip() == "locked"
        with pytest.raises(InputError, match=f"another run \\(pid {holder.pid}\\)"):
            with output_lock(tmp_path / "out"):
                pass
    finally:
        holder.kill()
        holder.wait()
    with output_lock(tmp_path / "out"):  # the lock of a killed holder is free
        pass


def _long_sweep(tmp_path: Path) -> Path:
    """The A-2.2 elastic sweep with 201 instead of 21 cases (several seconds: time to kill it while it stages)."""
    text = (SCENES / "wheel_rail_sweep_elastic.toml").read_text()
    text = text.replace("step = 0.5 }", "step = 0.05 }").replace("step = 0.0012 }", "step = 0.00012 }")
    path = tmp_path / "long_sweep.toml"
    path.write_text(text)
    return path


def _simulate(scene: Path, out: Path, *extra) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "contact", "simulate", str(scene), "--out", str(out), *extra],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=ENV, cwd=ROOT)


def _previous_output_and_a_staging_run(tmp_path: Path, out: Path, sig: int):
    """A finished run's files in ``out`` (name -> bytes), and a long wheel–rail run into ``out`` that has been sent
    ``sig`` while it was writing its staging folder."""
    first = _simulate(SCENES / "hertz_check.toml", out)
    assert first.wait(timeout=120) == 0, first.stderr.read()
    before = {str(p.relative_to(out)): p.read_bytes() for p in out.rglob("*") if p.is_file()}
    run = _simulate(_long_sweep(tmp_path), out)
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline and not list(tmp_path.glob(".out.staging-*")):
        time.sleep(0.05)
    time.sleep(0.3)
    run.send_signal(sig)
    return before, run


def test_killed_wheel_rail_run_leaves_the_previous_output_and_its_staging_is_cleaned(tmp_path):
    """kill -9 of a wheel–rail run while it computes: --out keeps the previous run's folder unchanged (never a
    mix); the hidden staging folder it leaves is removed by the next run into the same --out."""
    out = tmp_path / "out"
    before, run = _previous_output_and_a_staging_run(tmp_path, out, signal.SIGKILL)
    run.wait(timeout=30)
    assert list(tmp_path.glob(".out.staging-*")), "the run was not killed while staging"
    assert {str(p.relative_to(out)): p.read_bytes() for p in out.rglob("*") if p.is_file()} == before
    again = _simulate(SCENES / "hertz_check.toml", out)
    assert again.wait(timeout=120) == 0
    assert not list(tmp_path.glob(".out.*"))


def test_two_runs_into_one_out_never_mix(tmp_path):
    """Two runs started together into the same --out (one with pictures, one without): each either completes or
    is refused (exit 2, the lock); the folder holds the files of exactly one run."""
    out = tmp_path / "out"
    runs = [_simulate(SCENES / "hertz_check.toml", out, "--plots"), _simulate(SCENES / "paper_no_layer.toml", out)]
    codes = [r.wait(timeout=300) for r in runs]
    errs = [r.stderr.read() for r in runs]
    assert all(c in (0, 2) for c in codes) and 0 in codes, errs
    for c, e in zip(codes, errs):
        if c == 2:
            assert "another run" in e and e.count("\n") == 1, e
    result = json.loads((out / "result.json").read_text())
    pngs = {p.name for p in out.glob("*.png")}
    assert pngs == set(result.get("pictures", [])), (pngs, result.get("pictures"))
    assert Path(result["inputs"]["scene_file"]).name in ("hertz_check.toml", "paper_no_layer.toml")


def test_sigterm_removes_the_staging_folder_at_once(tmp_path):
    """SIGTERM (the usual ``kill``) of a wheel–rail run while it stages: exit 143 with one line, the staging
    folder is removed by the run itself, the previous output is unchanged."""
    out = tmp_path / "out"
    before, run = _previous_output_and_a_staging_run(tmp_path, out, signal.SIGTERM)
    rc = run.wait(timeout=60)
    assert rc == 143, run.stderr.read()[-3000:]
    assert run.stderr.read().strip() == "error: terminated (SIGTERM); nothing written"
    assert not list(tmp_path.glob(".out.*"))
    assert {str(p.relative_to(out)): p.read_bytes() for p in out.rglob("*") if p.is_file()} == before


def test_long_sweep_has_201_cases(tmp_path):
    import tomllib

    from contact.wheel_rail.parse import parse_wheel_rail_scene

    path = _long_sweep(tmp_path)
    assert len(parse_wheel_rail_scene(tomllib.loads(path.read_text()), path).cases) == 201


def test_staged_output_is_published_beside_out_until_it_finishes(tmp_path):
    """--out keeps the earlier output until finish(); each publish puts a complete snapshot into out.partial (files
    written later in the staging folder do not reach it); finish() puts the run in --out, keeps a user's file and
    removes out.partial; no staging left."""
    out, partial = tmp_path / "out", tmp_path / "out.partial"
    with replace_output_dir(out) as tmp:
        (tmp / "result.json").write_text('{"run": 0}')
        (tmp / "profiles").mkdir()
        (tmp / "profiles" / "old.prr").write_text("old")
    (out / "notes.txt").write_text("mine")
    before = {str(p.relative_to(out)): p.read_bytes() for p in out.rglob("*") if p.is_file()}
    owned = ("result.json", "profiles/")
    with staged_output_dir(out, owned=owned) as staged:
        atomic_write_text(staged.dir / "profiles" / "step_001.prr", "1")
        atomic_write_text(staged.dir / "result.json", '{"run": 1, "steps": 1}')
        assert not partial.exists()
        staged.publish()
        atomic_write_text(staged.dir / "profiles" / "step_002.prr", "2")
        atomic_write_text(staged.dir / "result.json", '{"run": 1, "steps": 2}')
        assert sorted(str(p.relative_to(partial)) for p in partial.rglob("*") if p.is_file()) == \
            ["profiles/step_001.prr", "result.json"]
        assert json.loads((partial / "result.json").read_text()) == {"run": 1, "steps": 1}
        staged.publish()
        assert staged.published == 2 and staged.where == partial
        assert {str(p.relative_to(out)): p.read_bytes() for p in out.rglob("*") if p.is_file()} == before
        staged.finish()
        assert staged.where == out and not partial.exists()
    assert json.loads((out / "result.json").read_text()) == {"run": 1, "steps": 2}
    assert (out / "notes.txt").read_text() == "mine" and not (out / "profiles" / "old.prr").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_a_foreign_partial_folder_is_refused(tmp_path):
    """A folder named like the partial-output folder but holding other content is never replaced."""
    (tmp_path / "out.partial").mkdir()
    (tmp_path / "out.partial" / "thesis.tex").write_text("mine")
    with pytest.raises(InputError, match="out.partial"):
        with staged_output_dir(tmp_path / "out"):
            pass
    assert (tmp_path / "out.partial" / "thesis.tex").read_text() == "mine"


def test_a_failed_write_names_its_path(tmp_path, monkeypatch):
    import errno

    def full(*args):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr("wrlayer.atomic_write.os.replace", full)
    with pytest.raises(OutputError) as err:
        atomic_write_text(tmp_path / "a.json", "{}")
    assert str(err.value) == f"{tmp_path / 'a.json'}: no space left on device"
    assert list(tmp_path.iterdir()) == []  # the temporary file removed


def test_an_interrupted_swap_is_undone_by_the_next_run(tmp_path):
    """A kill between the two renames of the non-atomic swap leaves the earlier output in an 'old' sibling: the
    next run into the same folder puts it back before anything else."""
    out = tmp_path / "out"
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True,
                          text=True).stdout.strip()
    old = tmp_path / f".out.old-{dead}-abc"
    (old / "out").mkdir(parents=True)
    (old / "out" / "result.json").write_text("{}")
    clean_stale_staging(out)
    assert (out / "result.json").read_text() == "{}" and not old.exists()


def test_sigterm_while_a_snapshot_is_removed_leaves_no_staging(tmp_path, monkeypatch, capsys):
    """A SIGTERM that arrives while a publish removes its snapshot (the previous output after the swap) cuts the
    removal short no more: the folder is removed to the end, then the run ends with 143 and keeps what it
    published. (Before, the half-removed snapshot stayed beside --out.)"""
    import shutil

    import wrlayer.atomic_write as aw
    from wrlayer.errors import cli_guard

    out = tmp_path / "out"
    real_rmtree = shutil.rmtree
    removals = []

    def rmtree_killed_halfway(path, ignore_errors=False):
        removals.append(Path(path))
        first = next((p for p in Path(path).rglob("*") if p.is_file()), None)
        if first is not None and len(removals) == 2:  # the snapshot of the second publish: the first output
            first.unlink()
            os.kill(os.getpid(), signal.SIGTERM)  # the handler runs at once; here it must not raise
        real_rmtree(path, ignore_errors=ignore_errors)

    monkeypatch.setattr(aw.shutil, "rmtree", rmtree_killed_halfway)

    @cli_guard
    def main():
        with staged_output_dir(out) as staged:
            for step in (1, 2, 3):
                for k in range(20):
                    atomic_write_text(staged.dir / f"step_{step}_{k}.txt", str(k))
                atomic_write_text(staged.dir / "result.json", json.dumps({"steps": step}))
                staged.publish()
        return 0

    assert main() == 143
    # the line says what was kept (it said "nothing written" while the steps were there)
    assert capsys.readouterr().err.strip() == \
        f"error: terminated (SIGTERM); the output published last is in {tmp_path / 'out.partial'}"
    assert len(removals) >= 2
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.partial"]  # no staging, snapshot or lock left
    assert json.loads((tmp_path / "out.partial" / "result.json").read_text()) == {"steps": 2}


def test_sigterm_while_a_staging_folder_is_made_leaves_none(tmp_path, monkeypatch, capsys):
    """A SIGTERM between the creation of a staging folder and its hand-over: the folder is removed, exit 143."""
    import tempfile

    import wrlayer.atomic_write as aw
    from wrlayer.errors import cli_guard

    real_mkdtemp = tempfile.mkdtemp

    def mkdtemp_then_killed(*args, **kwargs):
        made = real_mkdtemp(*args, **kwargs)
        os.kill(os.getpid(), signal.SIGTERM)
        return made

    monkeypatch.setattr(aw.tempfile, "mkdtemp", mkdtemp_then_killed)

    @cli_guard
    def main():
        with atomic_output_dir(tmp_path / "out") as tmp:
            (tmp / "result.json").write_text("{}")
        return 0

    assert main() == 143
    capsys.readouterr()
    assert list(tmp_path.iterdir()) == []
