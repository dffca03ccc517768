"""Entry points: bad command-line arguments and unusable output paths are one line with exit code 2."""

import pytest

from calibration.__main__ import main as calibration_main
from contact.__main__ import main as contact_main
from meshes.__main__ import main as meshes_main
from wrlayer.errors import ConvergenceError, InputError, cli_guard


@pytest.mark.parametrize("main,argv", [
    (contact_main, ["simulate", "scene.toml"]),                      # --out missing
    (contact_main, ["fly"]),
    (calibration_main, ["run", "cfg.toml", "--out", "o", "--workers", "two"]),
    (meshes_main, ["mesh", "60E1", "--y0", "abc", "--h-min", "1", "--h-max", "5", "--out", "m.vtu"]),
])
def test_bad_arguments_are_one_line_exit_2(main, argv, capsys):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    err = capsys.readouterr().err
    assert exc.value.code == 2
    assert err.count("\n") == 1 and err.startswith(("error: python -m ", "error: wrlayer ")), err


def test_unusable_out_is_one_line_exit_2(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    rc = contact_main(["simulate", "scenes/hertz_check.toml", "--out", str(blocker / "out")])
    err = capsys.readouterr().err
    assert rc == 2 and err.count("\n") == 1 and "cannot create the output folder" in err, err


def test_guard_maps_errors_to_exit_codes(capsys):
    def raiser(exc):
        @cli_guard
        def main():
            raise exc
        return main()

    assert raiser(InputError("a.toml: x", "bad")) == 2
    assert raiser(ConvergenceError("Newton")) == 3
    assert raiser(PermissionError(13, "Permission denied", "out/result.json")) == 2
    assert raiser(MemoryError()) == 3
    assert raiser(KeyboardInterrupt()) == 130
    lines = capsys.readouterr().err.splitlines()
    assert lines == ["error: a.toml: x: bad", "error: Newton", "error: out/result.json: Permission denied",
                     lines[3], "error: interrupted"] and lines[3].startswith("error: out of memory")
    with pytest.raises(ZeroDivisionError):  # a programming error keeps its traceback
        raiser(ZeroDivisionError())


def test_sigterm_swallowed_inside_a_c_callback_still_ends_the_run_without_output(tmp_path, capsys):
    """A SIGTERM whose Terminated is raised inside a C callback (numba's compiler calls back through ctypes) is
    dropped by Python; the run must still end with 143 and commit nothing (found in CI: the run went on)."""
    import ctypes
    import os
    import signal

    from wrlayer.atomic_write import atomic_output_dir

    out = tmp_path / "out"

    @ctypes.CFUNCTYPE(None)
    def callback():
        os.kill(os.getpid(), signal.SIGTERM)  # the handler runs here, inside the callback: its exception is dropped
        sum(range(1000))

    @cli_guard
    def main():
        callback()
        with atomic_output_dir(out) as tmp:
            (tmp / "result.json").write_text("{}")
        return 0

    assert main() == 143
    err = capsys.readouterr().err
    assert err.strip() == "error: terminated (SIGTERM); nothing written", err
    assert not out.exists() or not any(out.iterdir())


def test_an_error_caused_by_an_interrupted_library_call_after_sigterm_is_a_termination(capsys):
    """SIGTERM first, then a library turns the interrupted call into its own error (numba wraps exceptions raised
    while it compiles): the run ends as terminated (143), not with a traceback."""
    import os
    import signal

    import wrlayer.errors as errors

    @cli_guard
    def main():
        try:
            os.kill(os.getpid(), signal.SIGTERM)  # the handler raises right after this call, inside the try
            for _ in range(1000):
                pass
        except errors.Terminated:
            raise RuntimeError("a library's error made of the interruption") from None
        return 0

    assert main() == 143
    assert capsys.readouterr().err.strip() == "error: terminated (SIGTERM); nothing written"


def test_a_terminated_command_leaves_no_termination_behind(tmp_path, capsys):
    """A command ended by SIGTERM (143) leaves no flag behind: later library calls in the same process (the next
    test on the same pytest-xdist worker, a notebook) write their output instead of raising Terminated. (The flag
    once outlived the command: tests of atomic_write failed with Terminated depending on which worker ran them.)"""
    import os
    import signal

    from wrlayer.atomic_write import atomic_output_dir, replace_output_dir, staged_output_dir
    from wrlayer.errors import check_terminated, termination_deferred

    @cli_guard
    def main():
        with termination_deferred():
            os.kill(os.getpid(), signal.SIGTERM)  # held back to the end of the block, then raised
        return 0

    assert main() == 143
    capsys.readouterr()

    @cli_guard
    def failing():
        try:
            with termination_deferred():
                os.kill(os.getpid(), signal.SIGTERM)
                raise ValueError("an error leaving the deferred block")
        except ValueError:
            pass
        return 0

    assert failing() == 143  # the flag carried the SIGTERM past the error
    capsys.readouterr()
    check_terminated()
    with termination_deferred():
        pass
    with atomic_output_dir(tmp_path / "a") as tmp:
        (tmp / "result.json").write_text("{}")
    with replace_output_dir(tmp_path / "b") as tmp:
        (tmp / "result.json").write_text("{}")
    with staged_output_dir(tmp_path / "c") as staged:
        (staged.dir / "result.json").write_text("{}")
        staged.publish()
        staged.finish()
    assert all((tmp_path / name / "result.json").is_file() for name in "abc")
