"""A wear run killed at random moments (SIGKILL and SIGTERM) and run again into the same --out: after every kill
the folder holds either its previous content or the completed steps of the killed run with a result.json that
says where it stopped and lists exactly the folder's files; SIGTERM removes the staging folder within 2 s; the
next run cleans what a SIGKILL left and an earlier complete run is never lost without being replaced."""

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
KILLS = 20
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


@pytest.mark.slow
def test_random_kills_keep_the_promise(tmp_path, wear_dict, write_scene):
    rng = random.Random(20261126)
    scene = write_scene(wear_dict(layers=None, passes={"max": 4},
                                  wear={"distance_km": 40.0, "steps": STEPS, "inelastic": False}))
    out = tmp_path / "out"
    for _ in range(2):  # the second run, with warm caches, times the first step and the run
        t0 = time.monotonic()
        first, first_step = _start(scene, out), None
        while first.poll() is None:  # the kills aim at the steps mostly
            if first_step is None and (out / "result.json").is_file() and \
                    json.loads((out / "result.json").read_text())["status"].startswith("running"):
                first_step = time.monotonic() - t0
            time.sleep(0.02)
        assert first.returncode == 0, first.stderr.read()
        duration = time.monotonic() - t0
    first_step = first_step or 0.5 * duration
    assert _consistent(out) == ("complete", STEPS)
    outcomes: dict[str, int] = {}
    sigterm_exit_s = []
    for k in range(KILLS):
        before = _snapshot(out)
        sig = signal.SIGKILL if k % 2 == 0 else signal.SIGTERM
        run = _start(scene, out)
        before_steps = rng.random() < 0.25  # a quarter while it starts, the others around its steps
        time.sleep(rng.uniform(0.0, first_step) if before_steps else rng.uniform(0.8 * first_step, 1.05 * duration))
        t_kill = time.monotonic()
        run.send_signal(sig)
        rc = run.wait(timeout=60)
        err = run.stderr.read()
        if sig == signal.SIGTERM and rc != 0:  # 0: it had finished
            sigterm_exit_s.append(time.monotonic() - t_kill)
            assert rc in (143, -signal.SIGTERM), err  # -15: killed before the command installed its handler
            assert not list(tmp_path.glob(f".out.*-{run.pid}-*")), "SIGTERM left its staging folder"
        assert rc in (0, 143, -signal.SIGTERM, -signal.SIGKILL), err
        after = _snapshot(out)
        if after == before:
            outcome = "unchanged"
        else:
            status, n = _consistent(out)
            outcome = status.split(":")[0].split(" after")[0] + f" {n}"
            if sig == signal.SIGTERM and rc == 143:
                assert status in ("complete", f"terminated (SIGTERM) after step {n}"), status
        outcomes[f"{sig.name} {outcome}"] = outcomes.get(f"{sig.name} {outcome}", 0) + 1
    last = _start(scene, out)
    assert last.wait(timeout=300) == 0, last.stderr.read()
    assert _consistent(out) == ("complete", STEPS)
    assert not list(tmp_path.glob(".out.*"))  # what the SIGKILLs left is gone
    print(f"\n{KILLS} kills, run {duration:.1f} s (first step {first_step:.1f} s), SIGTERM exits {max(sigterm_exit_s, default=0):.2f} s at most:",
          dict(sorted(outcomes.items())))
    assert max(sigterm_exit_s, default=0.0) < 2.0
