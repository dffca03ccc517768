"""`python -m benchmarks` (make bench): a benchmark module without ``run(mode, out)`` (a command-line benchmark) is
listed as such in the report, not run and not reported as failed; an unknown name is refused (exit 2)."""

import importlib

from benchmarks.__main__ import discover, main


def test_a_command_line_benchmark_is_listed_not_failed(tmp_path, capsys):
    cli_only = [n for n in discover() if not callable(getattr(importlib.import_module(f"benchmarks.{n}"), "run", None))]
    assert "bench_layer_between" in cli_only
    assert main(["--quick", "--only", "layer_between", "--out", str(tmp_path)]) == 0
    report = (tmp_path / "report.md").read_text()
    assert "A command-line benchmark, not run here: `python -m benchmarks.bench_layer_between --help`" in report
    assert "FAILED" not in report
    assert main(["--only", "no_such_bench", "--out", str(tmp_path)]) == 2
    assert "unknown benchmark(s) ['bench_no_such_bench']" in capsys.readouterr().err
