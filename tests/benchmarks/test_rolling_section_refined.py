"""The refined section runs' bookkeeping: which case of each position is rolled again, its configuration (the gap's
at h = a/4, one level at the a/2 run's p0 in MPa) and the report read from a run's rolling.json."""

import json
from dataclasses import replace

import pytest

from benchmarks import rolling_section_refined as rf
from benchmarks.bench_rolling_section_gap import SectionGapRow
from benchmarks.rolling_section_cases import LEVELS, POSITIONS
from benchmarks.rolling_section_static import SectionStatic

NAME, TABLE, Y_MM, LABEL = POSITIONS[0]


def row(c, level, law_over_fem, static=0.01):
    fem = (0.010, 0.011, 0.012)
    return SectionGapRow(LABEL, c, level, 800.0, 790.0, static, 0.009, fem, tuple(law_over_fem * f for f in fem),
                         fem, fem)


def study(factor):
    dents = tuple(0.01 for _ in LEVELS)
    point = SectionStatic(NAME, 2.0, tuple(800.0 * x for x in LEVELS), dents, dents, 800.0, 1, 1.0)
    fine = SectionStatic(NAME, 4.0, point.p0_MPa, tuple(d * factor for d in dents), dents, 801.0, 2, 2.0)
    return {(NAME, 2.0): point, (NAME, 4.0): fine}


def test_the_worst_case_against_the_corrected_groove_is_chosen_per_position():
    rows = [row(0.0, 1.3, 1.04), row(0.2, 1.7, 0.93), row(0.0, 2.1, 1.06)]
    cases = rf.worst_cases(rows, study(1.05))  # corrected: 0.99, 0.886, 1.010
    assert len(cases) == 1  # only the first position has rows and a study
    case = cases[0]
    assert (case.label, case.c, case.level) == (LABEL, 0.2, 1.7)
    assert case.p0_MPa == pytest.approx(1.7 * 800.0)
    cfg = case.config()
    assert cfg.contact.levels == (pytest.approx(1360.0),) and cfg.contact.level_unit == "MPa"
    assert cfg.mesh.elements_per_semi_axis == rf.REFINED_ELEMENTS and cfg.contact.body == "section"
    assert cfg.contact.traction_coefficient == 0.2 and cfg.contact.y_mm == Y_MM


def test_report_compares_the_law_with_the_refined_groove(tmp_path):
    rows = [row(0.2, 1.7, 0.93)]
    st = study(1.05)
    case = rf.worst_cases(rows, st)[0]
    grooves = [0.0105, 0.0112, 0.0116, 0.0118, 0.0120]  # passes 1..5 at a/4
    run = {"n_dofs": 1234, "seconds": 56.0,
           "levels": [{"p0_MPa": 1360.0, "static_dent_mm": 0.0104, "groove_mm": grooves}]}
    (tmp_path / case.key).mkdir()
    (tmp_path / case.key / "rolling.json").write_text(json.dumps(run))
    text = rf.refined_markdown(rows, st, tmp_path)
    law = [0.93 * f / g for f, g in zip(rows[0].fem_mm, (grooves[0], grooves[1], grooves[4]))]
    assert ", ".join(f"{v:.3f}" for v in law) in text
    assert "| 1.040 |" in text  # static dent a/4 over a/2
    assert "in 0 of these 1 cases" in text  # law over the a/4 groove 0.886, 0.913, 0.930: not within 5 %
    assert "1234" in text
    moves = [(g / 0.0104) / (f / 0.01) - 1 for g, f in zip((grooves[0], grooves[1], grooves[4]), rows[0].fem_mm)]
    assert f"moved by {min(moves):+.1%} to {max(moves):+.1%}" in text


def test_an_incomplete_run_is_left_out(tmp_path):
    rows = [row(0.2, 1.7, 0.93)]
    case = rf.worst_cases(rows, study(1.05))[0]
    (tmp_path / case.key).mkdir()
    (tmp_path / case.key / "rolling.json").write_text(json.dumps(
        {"n_dofs": 1, "seconds": 1.0, "levels": [{"p0_MPa": 1.0, "static_dent_mm": 1.0, "groove_mm": [1.0]}]}))
    assert rf.refined_markdown(rows, study(1.05), tmp_path) == ""


def test_a_whole_position_is_every_level_and_traction_and_reported(tmp_path):
    rows = [row(0.0, 1.3, 1.04), row(0.2, 1.7, 0.93), row(0.0, 2.1, 1.06)]
    cases = rf.cases_of(rows, NAME)
    assert [(c.c, c.level) for c in cases] == [(0.0, 1.3), (0.2, 1.7), (0.0, 2.1)]
    assert rf.cases_of(rows, POSITIONS[1][0]) == []
    for case in cases[::2]:  # two runs, neither the worst case
        (tmp_path / case.key).mkdir()
        (tmp_path / case.key / "rolling.json").write_text(json.dumps(
            {"n_dofs": 1, "seconds": 1.0, "levels": [{"p0_MPa": case.p0_MPa, "static_dent_mm": 0.01,
                                                      "groove_mm": [0.0104, 0.0115, 0.012, 0.0125, 0.0126]}]}))
    text = rf.refined_markdown(rows, study(1.05), tmp_path)
    assert "| 1.3 |" in text and "| 2.1 |" in text and "| 1.7 |" not in text and "of these 2 cases" in text


def test_the_check_at_a6_reports_the_three_meshes_ratios(tmp_path):
    rows = [row(0.2, 1.7, 0.93)]
    case = rf.cases_of(rows, NAME)[0]
    assert rf.check_markdown(rows, tmp_path) == ""
    for elements, dent, grooves in ((4.0, 0.0104, [0.0105, 0.0112, 0.0116, 0.0118, 0.0120]),
                                    (6.0, 0.0106, [0.0107, 0.0114, 0.0117, 0.0119, 0.0121])):
        folder = tmp_path / replace(case, elements=elements).key
        folder.mkdir()
        (folder / "rolling.json").write_text(json.dumps(
            {"n_dofs": 99, "seconds": 7.0, "levels": [{"p0_MPa": case.p0_MPa, "static_dent_mm": dent,
                                                       "groove_mm": grooves}]}))
    assert folder.name.endswith("_h6")
    text = rf.check_markdown(rows, tmp_path)
    a4 = ", ".join(f"{g / 0.0104:.3f}" for g in (0.0105, 0.0112, 0.0120))
    a6 = ", ".join(f"{g / 0.0106:.3f}" for g in (0.0107, 0.0114, 0.0121))
    assert f"; {a4}; {a6} |" in text and f"| {0.0106 / 0.0104:.3f} |" in text and "| 99 |" in text
    law = ", ".join(f"{0.93 * f / g:.3f}" for f, g in zip(rows[0].fem_mm, (0.0107, 0.0114, 0.0121)))
    assert law in text


def test_a_long_run_compares_the_law_at_pass_10(tmp_path):
    rows = [row(0.2, 1.7, 0.93)]
    case = replace(rf.cases_of(rows, NAME)[0], passes=rf.LONG_PASSES)
    assert case.key.endswith("_h4_n10") and case.config().track.n_passes == rf.LONG_PASSES
    grooves = [0.0100 + 0.0002 * k for k in range(10)]
    (tmp_path / case.key).mkdir()
    run = {"n_dofs": 1, "seconds": 3.0, "levels": [{"p0_MPa": case.p0_MPa, "static_dent_mm": 0.01,
                                                  "groove_mm": grooves[:9]}]}
    (tmp_path / case.key / "rolling.json").write_text(json.dumps(run))
    law_of = lambda r, n: [1.0 + 0.03 * (k - 1) for k in n]  # noqa: E731
    assert rf.long_markdown(rows, tmp_path, law_of) == ""  # 9 of 10 passes: incomplete
    run["levels"][0]["groove_mm"] = grooves
    (tmp_path / case.key / "rolling.json").write_text(json.dumps(run))
    text = rf.long_markdown(rows, tmp_path, law_of)
    fem = [grooves[k - 1] / 0.01 for k in (1, 2, 5, 10)]
    assert ", ".join(f"{v:.3f}" for v in fem) in text
    assert ", ".join(f"{(1 + 0.03 * (k - 1)) / f:.3f}" for k, f in zip((1, 2, 5, 10), fem)) in text
