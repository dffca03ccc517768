"""Gmsh's first start in a process resets the process's signal dispositions behind Python's back (SIGTERM and
faulthandler's crash signals to their defaults, SIGPIPE no longer ignored); the project's sessions put them back.
Checked in fresh interpreters, whose dispositions no other test has touched and whose death would not take the
test run with it: one started bare (what Gmsh changes), one by the project's session."""

import os
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]

CHECK = textwrap.dedent("""
    import faulthandler, os, signal, sys
    import gmsh
    from meshes.meshing.gmsh_session import gmsh_session, initialize_gmsh

    def masks():
        return [line.split()[1] for line in open("/proc/self/status") if line.startswith(("SigIgn", "SigCgt"))]

    hit = []
    faulthandler.enable()
    signal.signal(signal.SIGTERM, lambda signum, frame: hit.append(signum))
    before = masks()
    if sys.argv[1] == "bare":
        gmsh.initialize(readConfigFiles=False, interruptible=False)
        gmsh.finalize()
        print(masks() != before)
        sys.exit(0)
    with gmsh_session("probe") as g:                                  # the first start: the project's session
        g.model.occ.addBox(0, 0, 0, 1, 1, 1)
        g.model.occ.synchronize()
        g.model.mesh.generate(3)
        inside = masks()
    after = masks()
    os.kill(os.getpid(), signal.SIGTERM)                              # the process's own handler runs
    print(inside == before, after == before, hit == [signal.SIGTERM])
""")


def _run(mode: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", CHECK, mode], capture_output=True, text=True, timeout=120,
                          cwd=ROOT, env={**os.environ, "PYTHONPATH": str(ROOT)})


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc/self/status")
def test_gmsh_sessions_keep_the_signal_dispositions():
    bare = _run("bare")
    assert bare.returncode == 0 and bare.stdout.split() == ["True"], (bare.stdout, bare.stderr)  # Gmsh changes them
    kept = _run("session")
    assert kept.returncode == 0, (kept.returncode, kept.stderr)     # -15: SIGTERM killed it, the handler was gone
    assert kept.stdout.split() == ["True"] * 3, kept.stdout
