"""Kalker's creepage coefficients (Table E3 of Kalker 1990): table values, limits, interpolation, trends."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from contact.tangential.kalker_coefficients import G_NODES, NU_NODES, SCALE_POWERS, TABLE, creep_coefficients
from wrlayer.errors import InputError


@pytest.mark.parametrize("a_over_b, nu, expected", [
    (1.0, 0.0, (3.40, 3.40, 1.33)),       # circle
    (1.0, 0.25, (4.12, 3.67, 1.47)),
    (1.0, 0.5, (5.20, 3.98, 1.63)),
    (0.5, 0.25, (3.62, 3.01, 0.929)),     # a/b = 0.5
    (2.0, 0.25, (5.10, 4.90, 2.62)),      # b/a = 0.5
    (0.1, 0.5, (4.85, 2.53, 0.731)),      # first table row
    (10.0, 0.0, (10.7, 10.7, 12.2)),      # b/a = 0.1
    (1 / 0.3, 0.5, (7.34, 7.51, 5.01)),
])
def test_published_table_values(a_over_b, nu, expected):
    c = creep_coefficients(a_over_b, nu)
    np.testing.assert_allclose((c.C11, c.C22, c.C23), expected, rtol=1e-9)


def test_both_branches_meet_at_the_circle_and_nu_zero_gives_c11_equal_c22():
    for nu in NU_NODES:
        lo, hi = creep_coefficients(1.0, nu), creep_coefficients(1.0 + 1e-12, nu)
        np.testing.assert_allclose((lo.C11, lo.C22, lo.C23), (hi.C11, hi.C22, hi.C23), rtol=1e-9)
    for ratio in (0.13, 0.5, 1.0, 2.7, 9.0):  # nu = 0: longitudinal and lateral problems are identical
        c = creep_coefficients(ratio, 0.0)
        assert c.C11 == pytest.approx(c.C22, rel=1e-12)


def test_interpolation_between_nodes_is_linear_in_the_scaled_coefficients_and_in_nu():
    t = TABLE["b<a"]
    # b/a = 0.15 (a/b = 1/0.15): halfway between rows g = 0.1 and 0.2; nu = 0.125 halfway between columns 0, 0.25
    c = creep_coefficients(1 / 0.15, 0.125)
    for name, value in (("C11", c.C11), ("C22", c.C22), ("C23", c.C23)):
        q = SCALE_POWERS["b<a"][name]
        expected = 0.25 * (0.1 ** q * (t[name][0, 0] + t[name][0, 1]) + 0.2 ** q * (t[name][1, 0] + t[name][1, 1]))
        assert value == pytest.approx(expected / 0.15 ** q, rel=1e-9)
    # value between two nodes lies between them
    lo, mid, hi = (creep_coefficients(0.4, 0.28), creep_coefficients(0.45, 0.28), creep_coefficients(0.5, 0.28))
    assert lo.C23 < mid.C23 < hi.C23


@pytest.mark.parametrize("branch", ["a<=b", "b<a"])
def test_interpolation_predicts_the_published_rows_within_2_percent(branch):
    """Each inner row of Table E3 predicted from the rows two apart (twice the table's spacing, so a harsher test
    than between neighbouring rows) by the rule's scaled interpolation: within 2 % of Kalker's published value. The
    coefficients themselves interpolated linearly in g (CONTACT's rule) miss C23 at b/a = 0.2 by 46 %."""
    for name in ("C11", "C22", "C23"):
        t, q = TABLE[branch][name], SCALE_POWERS[branch][name]
        for r in range(1, G_NODES.size - 1):
            g0, g, g1 = G_NODES[r - 1], G_NODES[r], G_NODES[r + 1]
            predicted = 0.5 * (g0 ** q * t[r - 1] + g1 ** q * t[r + 1]) / g ** q
            np.testing.assert_allclose(predicted, t[r], rtol=0.02, err_msg=f"{branch} {name} g = {g:.1f}")
    linear = 0.5 * (TABLE["b<a"]["C23"][0] + TABLE["b<a"]["C23"][2])
    assert np.max(linear / TABLE["b<a"]["C23"][1]) > 1.4


def test_asymptotes_below_the_table_are_close_to_the_last_rows():
    for nu in NU_NODES:
        for ratio_in, ratio_out in ((0.1, 0.0999), (10.0, 10.01)):
            tab, asy = creep_coefficients(ratio_in, nu), creep_coefficients(ratio_out, nu)
            for name in ("C11", "C22", "C23"):
                assert getattr(asy, name) == pytest.approx(getattr(tab, name), rel=0.07)
    # a/b -> 0: C11 -> pi^2 / (4 (1 - nu)), C22 -> pi^2/4 (Kalker's strip limit)
    c = creep_coefficients(1e-4, 0.25)
    assert c.C11 == pytest.approx(np.pi**2 / 4 / 0.75) and c.C22 == pytest.approx(np.pi**2 / 4)
    # b/a -> 0: coefficients grow without bound (C11 roughly like 1/(g log(1/g)))
    assert creep_coefficients(1e3, 0.25).C11 > 30 * creep_coefficients(10.0, 0.25).C11


@settings(max_examples=60, deadline=None)
@given(st.floats(0.1, 10.0), st.floats(0.0, 0.5))
def test_monotonic_trends(ratio, nu):
    c = creep_coefficients(ratio, nu)
    assert c.C11 > 0 and c.C22 > 0 and c.C23 > 0
    # C22 and C23 grow with a/b (C11 does not for a < b and nu = 0.5: 4.85, 4.81, 4.80, ... in the table)
    up = creep_coefficients(min(ratio * 1.2, 10.0), nu)
    assert up.C22 >= c.C22 - 1e-12 and up.C23 >= c.C23 - 1e-12
    if ratio >= 1.0:
        assert up.C11 >= c.C11 - 1e-12
    # all three grow with Poisson's ratio
    stiffer = creep_coefficients(ratio, min(nu + 0.05, 0.5))
    assert stiffer.C11 >= c.C11 - 1e-12 and stiffer.C22 >= c.C22 - 1e-12 and stiffer.C23 >= c.C23 - 1e-12


def test_table_rows_are_monotonic():
    for branch, sign in (("a<=b", 1), ("b<a", -1)):  # g = a/b grows / g = b/a grows -> a/b falls
        for name in ("C22", "C23"):
            assert np.all(sign * np.diff(TABLE[branch][name], axis=0) > 0), (branch, name)
    assert G_NODES[0] == pytest.approx(0.1) and G_NODES[-1] == pytest.approx(1.0)


@pytest.mark.parametrize("ratio, nu, what", [
    (0.0, 0.25, "a_over_b"), (-1.0, 0.25, "a_over_b"), (np.nan, 0.25, "a_over_b"), (np.inf, 0.25, "a_over_b"),
    (1.0, -0.1, "poisson"), (1.0, 0.51, "poisson"), (1.0, np.nan, "poisson"),
])
def test_bad_input_names_the_argument(ratio, nu, what):
    with pytest.raises(InputError, match=what):
        creep_coefficients(ratio, nu)
