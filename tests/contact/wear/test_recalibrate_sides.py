"""The sides of a wear step's recalibration: a side whose worn profiles and anchors equal an earlier side's (a
mirror-symmetric run, round-off apart) takes that side's tables instead of a second calibration."""

import numpy as np

from contact.wear import recalibrate as recal_mod
from contact.wear.recalibrate import (SAME_PROFILE_MM, SideTables, recalibrate_sides, same_profile_files,
                                     write_profiles)
from meshes.profiles import SplineProfile, get_profile


def nudged(profile, dz_mm: float, at: int = 10):
    """``profile`` as a spline through its points (sampled every 0.2 mm) with one z moved by ``dz_mm``."""
    pts = profile.points.copy() if isinstance(profile, SplineProfile) else np.column_stack(profile.sample(0.2))
    pts[at, 1] += dz_mm
    return SplineProfile(pts[:, 0], pts[:, 1], f"{profile.name} nudged", profile.body)


def sides(dz_mm: float):
    rail = nudged(get_profile("60E1"), 0.0)
    return {"right": {"rail": rail}, "left": {"rail": nudged(rail, dz_mm)}}


def counting(monkeypatch):
    calls = []

    def fake(recal, profiles, work, scheduler="", what="", anchors=None, files=None):
        assert files == {"rail": (work / "rail.prr").resolve()} and files["rail"].is_file()  # written once, passed on
        calls.append((work.name, anchors))
        return SideTables({"rail": object()}, {("rail", float(len(calls))): object()})

    monkeypatch.setattr(recal_mod, "recalibrate_side", fake)
    return calls


def test_round_off_apart_the_profiles_are_the_same(tmp_path):
    def files(profiles, name):
        return write_profiles(profiles, tmp_path / name, "test")

    right, left = sides(1e-14).values()
    assert same_profile_files(files(right, "r"), files(left, "l"))
    assert not same_profile_files(files(right, "r"), files(sides(10 * SAME_PROFILE_MM)["left"], "far"))
    assert not same_profile_files(files(right, "r"), {})


def test_a_mirror_side_takes_the_earlier_sides_tables(monkeypatch, tmp_path):
    calls = counting(monkeypatch)
    tables, after = recalibrate_sides(object(), sides(1e-14), 1, tmp_path)
    assert [c[0] for c in calls] == ["step_001_right"]
    assert tables["left", "rail"] is tables["right", "rail"] and after["left"] is after["right"]
    assert (tmp_path / "calibration" / "step_001_left" / "rail.prr").is_file()  # its worn profile is kept


def test_different_profiles_or_anchors_are_calibrated_each(monkeypatch, tmp_path):
    calls = counting(monkeypatch)
    recalibrate_sides(object(), sides(1e-3), 1, tmp_path)
    assert [c[0] for c in calls] == ["step_001_right", "step_001_left"]
    calls.clear()
    anchors = {"right": {("rail", 0.0): "a"}, "left": {("rail", 0.0): "b"}}
    recalibrate_sides(object(), sides(0.0), 2, tmp_path, anchors=anchors)
    assert [c[1] for c in calls] == [anchors["right"], anchors["left"]]
    assert np.isfinite(SAME_PROFILE_MM)
