"""Shared wheel/rail objects for the geometry tests (built once per session)."""

import pytest

from contact.wheel_rail.track_geometry import TrackLayout, place_rail
from meshes.profiles import S1002, Rail60E1


@pytest.fixture(scope="session")
def layout():
    return TrackLayout()


@pytest.fixture(scope="session")
def rail60():
    return Rail60E1()


@pytest.fixture(scope="session")
def s1002():
    return S1002()


@pytest.fixture(scope="session")
def placed(rail60, layout):
    return place_rail(rail60, layout)
