"""benchmarks/bench_similarity_reuse.py on synthetic ratios: pairs of profiles are classed by how far the patch
moved (the reuse limits, the anchor's), and the chain of recalibrations solves a position only when its patch left
the one it was last solved at."""

import math

from benchmarks.bench_similarity_reuse import markdown, pair_classes, solves_along, within
from calibration.similarity.anchor import ANCHOR_LIMITS
from calibration.similarity.elastic import REUSE_LIMITS


def _patch(a=6.0, b=4.0, c=0.01, p_y=1.0, c_el=1.0):
    return {"a": a, "b": b, "c": c, "p_y": p_y, "c_el": c_el}


def test_within_checks_convexity_aspect_and_size():
    ref = _patch()
    assert within(ref, _patch(), REUSE_LIMITS)
    assert within(ref, _patch(c=0.01 + 0.99 * REUSE_LIMITS.convexity), REUSE_LIMITS)
    assert not within(ref, _patch(c=0.01 + 1.01 * REUSE_LIMITS.convexity), REUSE_LIMITS)
    assert not within(ref, _patch(a=6.0 * 1.01 * REUSE_LIMITS.aspect_factor), REUSE_LIMITS)
    grown = REUSE_LIMITS.size_factor * 1.01
    assert not within(ref, _patch(a=6.0 * grown, b=4.0 * grown), REUSE_LIMITS)
    assert within(ref, _patch(a=6.0 * grown, b=4.0 * grown), ANCHOR_LIMITS)


def test_pairs_are_classed_by_how_far_the_patch_moved_and_carry_the_ratio_changes():
    ratios = {"one": {("rail", 0.0): _patch(), ("rail", 5.0): _patch(), ("rail", 9.0): _patch()},
              "two": {("rail", 0.0): _patch(p_y=1.001),                       # the same patch, re-solved
                      ("rail", 5.0): _patch(c=0.02, p_y=1.002, c_el=1.01),   # within the reuse limits
                      ("rail", 9.0): _patch(a=12.0, p_y=1.01)}}              # a/b x2: beyond the reuse limits
    classes = pair_classes(ratios)
    assert [len(v) for v in classes.values()] == [1, 1, 1, 0]
    assert math.isclose(classes["same patch"][0][0], 0.1, rel_tol=1e-9)
    assert math.isclose(classes["within the reuse limits"][0][1], 1.0, rel_tol=1e-9)
    assert math.isclose(classes["within the anchor's limits"][0][0], 1.0, rel_tol=1e-9)


def test_a_position_is_solved_again_only_when_its_patch_left_the_one_last_solved():
    drift = [_patch(a=6.0 * 1.2 ** k) for k in range(4)]  # a/b grows x1.2 a step: x1.44 after two
    ratios = {f"step {k}": {("wheel", 0.0): drift[k], ("rail", 0.0): _patch()} for k in range(4)}
    assert solves_along(ratios, ["step 0", "step 1", "step 2", "step 3"]) == [0, 1, 0]


def test_the_report_lists_every_class_with_the_limits_and_the_solves():
    stats = {k: {"pairs": 2, "p_y": [0.1, 0.2, 0.3], "c_el": [0.1, 0.2, 0.3]}
             for k in ("same patch", "within the reuse limits", "within the anchor's limits", "beyond")}
    text = markdown({"states": ["step 0", "step 1"], "classes": stats, "solves": [3], "positions": 27})
    assert f"within the reuse limits (b/(2R) {REUSE_LIMITS.convexity:g}" in text
    assert "| beyond | 2 | 0.100 / 0.200 / 0.300 |" in text
    assert "(after steps 1..1, right side): 3 of 27 positions" in text
