"""benchmarks.same_results: equal folders agree; a changed number, cell, line or file is found; run times are not."""

import json

from benchmarks.same_results import main


def _folder(tmp_path, name, p_max=1516.88, time_s=0.09, cell="0.5", extra=False):
    folder = tmp_path / name
    (folder / "scene").mkdir(parents=True)
    record = {"code_version": f"git {name}", "passes": [{"p_max_MPa": p_max, "timings_s": {"normal_s": time_s}}]}
    (folder / "scene" / "result.json").write_text(json.dumps(record))
    (folder / "scene" / "cases.csv").write_text(f"case,p_max_MPa,time_s\n0,{cell},{time_s}\n")
    (folder / "table.md").write_text(f"| scene | p_max MPa |\n| a | {p_max} |\nrun in {time_s} s\n")
    if extra:
        (folder / "scene" / "more.csv").write_text("a\n1\n")
    return folder


def test_same_numbers_other_run_times_agree(tmp_path, capsys):
    assert main([str(_folder(tmp_path, "a")), str(_folder(tmp_path, "b", time_s=1.7))]) == 0
    assert "0 difference(s)" in capsys.readouterr().out


def test_changed_number_cell_and_file_are_found(tmp_path, capsys):
    before = _folder(tmp_path, "a")
    assert main([str(before), str(_folder(tmp_path, "b", p_max=1516.8801))]) == 1
    assert main([str(before), str(_folder(tmp_path, "c", cell="0.6"))]) == 1
    assert main([str(before), str(_folder(tmp_path, "d", extra=True))]) == 1
    out = capsys.readouterr().out
    assert "passes[0].p_max_MPa" in out and "table.md:2" in out
    assert "cases.csv:2: p_max_MPa '0.5' before, '0.6' after" in out
    assert "more.csv: only after" in out


def test_missing_folder_is_bad_input(tmp_path, capsys):
    assert main([str(tmp_path / "none"), str(tmp_path)]) == 2
    assert capsys.readouterr().err.startswith("error: ")
