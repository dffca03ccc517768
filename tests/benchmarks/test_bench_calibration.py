"""The calibration benchmark's own steps: the end-to-end contact pass through the contact API (no subprocess) and
the `make calibrate` times read from the last run's summary."""

import json

import benchmarks.bench_calibration as bc


def test_end_to_end_pass_runs_the_scene_through_the_api(tmp_path, capsys):
    table = bc.ROOT / "scenes" / "tables" / "rail_60E1_default.json"
    p = bc._contact_first_pass(table, False, tmp_path, "crown")
    assert (tmp_path / "crown" / "result.json").is_file()
    assert 10.0 < p["length_mm"] < 20.0 and 8.0 < p["width_mm"] < 15.0  # the crown patch at 100 kN
    assert 900.0 < p["p_max_MPa"] < 1300.0 and p["up0_mm"] > 0.0        # above first yield: a dent
    assert "deprecated" not in capsys.readouterr().err                   # the scene uses today's keys


def test_make_times_reads_the_last_summary(tmp_path, monkeypatch):
    monkeypatch.setattr(bc, "DEFAULT_OUT", tmp_path)
    assert bc.make_times(False) == {}
    (tmp_path / "summary.json").write_text(json.dumps({"seconds": 12.5, "positions_computed": 3,
                                                       "fem_seconds": 30.0}))
    assert bc.make_times(False) == {"last_run_s": 12.5, "last_run_computed": 3, "last_run_fem_seconds": 30.0}
