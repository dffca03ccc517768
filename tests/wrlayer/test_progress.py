"""Progress on stderr: a bar on a terminal, one line per item in a log, nothing when quiet."""

import pytest

from wrlayer.progress import ProgressBar, progress, progress_mode


@pytest.mark.parametrize("env, quiet, mode", [("lines", False, "lines"), ("1", False, "bar"), ("0", False, "off"),
                                              ("lines", True, "off")])
def test_mode_from_environment_and_quiet(monkeypatch, env, quiet, mode):
    monkeypatch.setenv("WRLAYER_PROGRESS", env)
    assert progress_mode(quiet) == mode


def test_log_gets_one_line_per_item_when_stderr_is_not_a_terminal(monkeypatch, capsys):
    monkeypatch.delenv("WRLAYER_PROGRESS")
    assert progress_mode() == "lines"  # pytest's captured stderr is not a terminal
    assert list(progress([10, 20, 30], desc="cases", unit="case")) == [10, 20, 30]
    err = capsys.readouterr().err.splitlines()
    assert [line.split(" (")[0] for line in err] == ["cases: 1/3 case", "cases: 2/3 case", "cases: 3/3 case"]
    assert all(line.endswith(" s)") for line in err)


def test_secondary_counters_stay_silent_in_a_log(monkeypatch, capsys):
    monkeypatch.setenv("WRLAYER_PROGRESS", "lines")
    list(progress(range(5), desc="passes", lines=False))
    with ProgressBar(4, "load stages", "stage", lines=False) as bar:
        bar.update(4)
    with ProgressBar(2, "positions", "pos") as bar:
        bar.update()
        bar.grow_total(3)
        bar.update()
    assert capsys.readouterr().err.splitlines()[1].startswith("positions: 2/3 pos (")


def test_quiet_prints_nothing(monkeypatch, capsys):
    monkeypatch.setenv("WRLAYER_PROGRESS", "lines")
    list(progress(range(3), desc="cases", quiet=True))
    bar = ProgressBar(3, "steps", quiet=True)
    bar.update()
    bar.reset(5)
    assert (bar.n, bar.total) == (0, 5)
    assert capsys.readouterr().err == ""
