"""benchmarks.harness.publish: a benchmark's markdown printed, and with a report path written there stamped with the
command that regenerates it."""

from benchmarks import harness


def test_the_markdown_is_printed_and_written_stamped_only_when_a_report_is_asked(tmp_path, capsys):
    harness.publish(None, "Title", "| a |\n", "python -m benchmarks.bench_x", ["--y"])
    assert capsys.readouterr().out == "| a |\n\n" and not list(tmp_path.iterdir())
    report = tmp_path / "sub" / "r.md"
    harness.publish(report, "Title", "| a |", "python -m benchmarks.bench_x", ["--report", str(report)])
    text = report.read_text()
    assert text.startswith("# Title\n\nRevision ") and text.rstrip().endswith("| a |")
    assert f"regenerate: `python -m benchmarks.bench_x --report {report}`" in text
    assert capsys.readouterr().out == "| a |\n"
