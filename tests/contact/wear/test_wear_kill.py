"""A wear run killed at random moments (SIGKILL and SIGTERM) and run again into the same --out that holds an
earlier complete run: after every kill --out holds that earlier run unchanged (or the killed run had completed and
replaced it); the killed run's completed steps are in --out.partial with a result.json that says where it stopped
and lists exactly the folder's files; SIGTERM prints one line saying exactly that and removes its staging folder
without waiting for the step; the next complete run removes what a SIGKILL left and the partial folder."""

import json
import os
import random
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
ENV = {**os.environ, "PYTHONPATH": str(ROOT), "MPLBACKEND": "Agg", "WRLAYER_PROGRESS": "0"}
KILLS = 12  # the kills land on every phase (start, steps, publishing) at this count; 20 cost 100 s of make test
STEPS = 3
STATUS = re.compile(r"complete|running: (\d+) steps completed|terminated \(SIGTERM\) after step (\d+)")


def _start(scene: Path, out: Path) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, "-m", "contact", "wear", str(scene), "--out", str(out), "--quiet",
                             "--no-plots"], env=ENV, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            text=True)


def _snapshot(out: Path) -> dict[str, bytes]:
    return {str(p.relative_to(out)): p.read_bytes() for p in sorted(out.rglob("*")) if p.is_file()}


def _consistent(out: Path) -> tuple[str, int]:
    """Assert that ``out`` is one self-consistent published state; returns (status, completed steps)."""
    res = json.loads((out / "result.json").read_text())
    match = STATUS.fullmatch(res["status"])
    assert match, res["status"]
    steps = [s["step"] for s in res["steps"]]
    assert steps == list(range(1, len(steps) + 1)) and steps, steps
    n = int(match.group(1) or match.group(2) or len(steps))
    assert n == len(steps), (res["status"], steps)
    if res["status"] == "complete":
        assert res["distance_done_km"] == pytest.approx(40.0)
    listed = {"result.json", "steps.csv"}
    listed |= {f for item in res["initial"]["profiles"] for f in item["files"]}
    for step in res["steps"]:
        for item in step["files"]:
            listed |= set(item["files"]) | {item["depth_file"]}
    assert set(_snapshot(out)) == listed  # every listed file there, nothing of another step or run
    rows = (out / "steps.csv").read_text().strip().splitlines()
    assert len(rows) == 1 + 2 * n
    return res["status"], n


def _wait_for_publish(run: subprocess.Popen, folders: dict[Path, bytes | None], timeout: float = 120.0,
                      steps: int = 1) -> None:
    """Until the run has published ``steps`` steps (the result.json of one of ``folders`` differs from the bytes
    given and lists that many: ``--out.partial``, or ``--out`` itself for a run that publishes there) or has
    ended."""
    deadline = time.monotonic() + timeout
    while run.poll() is None and time.monotonic() < deadline:
        for folder, old in folders.items():
            try:
                now = (folder / "result.json").read_bytes()
                if now != old and len(json.loads(now)["steps"]) >= steps:
                    return
            except (OSError, ValueError, KeyError):
                pass
        time.sleep(0.01)


def _sigterm_line(err: str, out: Path, partial: Path, partial_changed: bool, out_changed: bool) -> None:
    """The one line of an exit 143 says what the kill kept, matching the folders."""
    line = err.strip()
    assert line.count("\n") == 0, err
    if out_changed:
        assert line == f"error: terminated (SIGTERM); the complete run ({STEPS} steps) is in {out}", line
    elif partial_changed:
        _, n = _consistent(partial)
        assert line == (f"error: terminated (SIGTERM); {n} completed step(s) kept in {partial}; {out} keeps the "
                        "earlier output"), line
    else:
        assert line == "error: terminated (SIGTERM); nothing written", line


@pytest.mark.slow
def test_random_kills_never_lose_the_earlier_output(tmp_path, wear_dict, write_scene):
    rng = random.Random(20261126)
    scene = write_scene(wear_dict(layers=None, passes={"max": 4},
                                  wear={"distance_km": 40.0, "steps": STEPS, "inelastic": False}))
    out, partial = tmp_path / "out", tmp_path / "out.partial"
    for _ in range(2):  # the second run, with warm caches, times the first step and the run
        t0 = time.monotonic()
        first, first_step = _start(scene, out), None
        while first.poll() is None:  # the kills aim at the steps mostly
            if first_step is None and (partial / "result.json").is_file():
                first_step = time.monotonic() - t0
            time.sleep(0.02)
        assert first.returncode == 0, first.stderr.read()
        duration = time.monotonic() - t0
    first_step = first_step or 0.5 * duration
    assert _consistent(out) == ("complete", STEPS) and not partial.exists()
    outcomes: dict[str, int] = {}
    sigterm_exit_s = []
    for k in range(KILLS):
        before, partial_before = _snapshot(out), _snapshot(partial) if partial.exists() else None
        sig = signal.SIGKILL if k % 2 == 0 else signal.SIGTERM
        run = _start(scene, out)
        phase = rng.random()
        if phase < 0.25:  # a quarter while it starts
            time.sleep(rng.uniform(0.0, first_step))
        else:  # the others once it has published a step (or a later one: the steps themselves are hit on any
            # machine, however fast the run after its first step), then up to the end of the run
            steps = rng.randint(1, STEPS - 1) if phase < 0.75 else 1
            _wait_for_publish(run, {partial: (partial_before or {}).get("result.json"),
                                    out: before["result.json"]}, steps=steps)
            time.sleep(rng.uniform(0.0, (0.1 if phase < 0.75 else 1.1) * (duration - first_step)))
        t_kill = time.monotonic()
        run.send_signal(sig)
        rc = run.wait(timeout=60)
        err = run.stderr.read()
        assert rc in (0, 143, -signal.SIGTERM, -signal.SIGKILL), err
        after = _snapshot(out)
        out_changed = after != before
        if out_changed:  # only a run that ended replaces the earlier output
            assert _consistent(out) == ("complete", STEPS)
            assert sig == signal.SIGKILL or not partial.exists()  # kill -9 may fall between the two
        partial_after = _snapshot(partial) if partial.exists() else None
        partial_changed = partial_after is not None and partial_after != partial_before
        if partial_changed:
            status, n = _consistent(partial)
            assert status != "complete" and 1 <= n < STEPS + 1, status
        if sig == signal.SIGTERM and rc != 0:  # 0: it had finished
            sigterm_exit_s.append(time.monotonic() - t_kill)
            assert rc in (143, -signal.SIGTERM), err  # -15: killed before the command installed its handler
            assert not list(tmp_path.glob(f".out*.*-{run.pid}-*")), "SIGTERM left its staging folder"
            if rc == 143:
                _sigterm_line(err, out, partial, partial_changed, out_changed)
                if partial_changed:
                    assert _consistent(partial)[0] == f"terminated (SIGTERM) after step {_consistent(partial)[1]}"
        outcome = "complete" if out_changed else f"partial {_consistent(partial)[1]}" if partial_changed \
            else "unchanged"
        outcomes[f"{sig.name} {outcome}"] = outcomes.get(f"{sig.name} {outcome}", 0) + 1
    last = _start(scene, out)
    assert last.wait(timeout=300) == 0, last.stderr.read()
    assert _consistent(out) == ("complete", STEPS)
    assert not partial.exists() and not list(tmp_path.glob(".out*"))  # what the kills left is gone
    print(f"\n{KILLS} kills, run {duration:.1f} s (first step {first_step:.1f} s), SIGTERM exits "
          f"{max(sigterm_exit_s, default=0):.2f} s at most:", dict(sorted(outcomes.items())))
    assert sum(v for k, v in outcomes.items() if "partial" in k) >= KILLS // 4  # the kills did hit the steps
    # that SIGTERM ended the run without finishing it is asserted by the statuses above; its exit time is printed
    # for the record, not asserted (0.8-1.2 s idle, up to 11 s at load 20 on 2 cores: a timing, not a behaviour)
