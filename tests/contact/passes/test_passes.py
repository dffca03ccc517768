"""Repeated passes: dents added to the separation, shakedown at p_2, strain hardening, per-body records. The paper's
passes are Kik-Piotrowski's (named; the default normal method is the half-space on a coarse grid)."""

import numpy as np
import pytest

from wrlayer.characteristic import Characteristic
from contact.normal.kik_piotrowski import solve_normal
from contact.scenes.paper_example import PAPER_EXAMPLE, paper_characteristic, paper_layers, paper_problem
from contact.passes.passes import PassesOptions, run_passes
from contact.layer.prandtl_layer import LayerPair, PrandtlLayer
from wrlayer.errors import InputError


@pytest.fixture(scope="module")
def paper_run():
    prob = paper_problem()
    return prob, *run_passes(prob, paper_layers(prob), PassesOptions(max_passes=80, tolerance_mm=1e-6),
                                   method="kik_piotrowski")


def test_shakedown_ends_at_the_elastic_limit(paper_run):
    prob, records, final_f = paper_run
    last = records[-1]
    p2 = paper_characteristic().elastic_limit_MPa
    assert last.shakedown and len(records) < 80
    assert last.max_residual_mm <= 1e-6
    assert p2 <= last.p_max_MPa <= p2 + 0.5            # residual 1e-6 mm <=> p_0 - p_2 ~ 0.05 MPa
    p = np.array([r.p_max_MPa for r in records])
    area = np.array([r.area_mm2 for r in records])
    assert np.all(np.diff(p) < 0) and area[-1] > area[0]
    assert records[0].up0_mm == pytest.approx(float(paper_characteristic().residual_displacement(p[0])), rel=1e-12)


def test_dents_enter_the_separation(paper_run):
    prob, records, final_f = paper_run
    dent = records[-1].cumulative_residual_mm["combined"]
    np.testing.assert_allclose(final_f - prob.separation_unshifted_on_grid_mm, dent, atol=1e-15)
    # re-solving the last pass from the records reproduces it
    second_last = records[-2].cumulative_residual_mm["combined"]
    again = solve_normal(prob.with_offset(second_last), paper_layers(prob))
    assert again.delta_mm == pytest.approx(records[-1].delta_mm, rel=1e-9)


def test_paper_tolerance_stops_near_19_cycles():
    prob = paper_problem()
    records, _ = run_passes(prob, paper_layers(prob),
                            PassesOptions(tolerance_mm=PAPER_EXAMPLE["shakedown_tolerance_mm"]),
                            method="kik_piotrowski")
    assert 17 <= len(records) <= 22
    assert records[-1].p_max_MPa == pytest.approx(1190.0, rel=0.01)


def test_hardening_shakes_down_faster_and_keeps_the_state():
    prob = paper_problem()
    calls = []
    records, _ = run_passes(prob, paper_layers(prob), PassesOptions(hardening=True),
                            on_pass=lambda rec, sol: calls.append((rec.index, sol.delta_mm)), method="kik_piotrowski")
    assert len(records) <= 6 and records[-1].shakedown
    assert [c[0] for c in calls] == [r.index for r in records]
    assert all(r.up0_mm <= 1e-12 for r in records[1:])        # reference element reloads below its old peak
    assert records[-1].p_max_MPa > 1400.0                      # no shakedown to p_2: hardened elements


def test_two_bodies_keep_separate_dents():
    prob = paper_problem()
    cw = Characteristic([0.0, 0.01, 0.03], [0.0, 1000.0, 1500.0])
    cr = Characteristic([0.0, 0.02, 0.05], [0.0, 1300.0, 1700.0])
    pair = LayerPair(wheel=PrandtlLayer.uniform(cw, prob.strip_y_mm), rail=PrandtlLayer.uniform(cr, prob.strip_y_mm))
    records, final_f = run_passes(prob, pair, PassesOptions(max_passes=3))
    assert len(records) == 3 and np.all(pair.wheel.u_mm == 0)    # caller's layers untouched
    first = records[0]
    j = np.argmax(first.p_peak_MPa)
    assert first.cumulative_residual_mm["wheel"][j] == pytest.approx(
        float(cw.residual_displacement(first.p_peak_MPa[j])), rel=1e-12)
    assert first.cumulative_residual_mm["rail"][j] == pytest.approx(
        float(cr.residual_displacement(first.p_peak_MPa[j])), rel=1e-12, abs=1e-18)
    total = sum(records[-1].cumulative_residual_mm.values())
    np.testing.assert_allclose(final_f - prob.separation_unshifted_on_grid_mm, total, atol=1e-15)


def test_without_layer_one_elastic_pass():
    records, _ = run_passes(paper_problem(), None)
    assert len(records) == 1 and records[0].shakedown and records[0].max_residual_mm == 0.0


def test_bad_options():
    with pytest.raises(InputError, match="max_passes"):
        PassesOptions(max_passes=0)
