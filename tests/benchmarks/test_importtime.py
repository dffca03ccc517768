"""``benchmarks/importtime.py`` (used by ``benchmarks/bench_startup.py``): parsing ``python -X importtime``
output, the import total, the grouping by package with the importer of its heaviest part, and the scan for
module-level imports."""

import pytest

from benchmarks.importtime import (group_of, import_groups, import_seconds, lazy_library_seconds,
                                   module_level_importers, parse_importtime)

# children print before the module that imported them; the name is indented two spaces per level
SAMPLE = """\
import time: self [us] | cumulative | imported package
import time:       185 |        185 |   _io
import time:       699 |       1403 | encodings
some line the command printed itself
import time:       300 |        300 |       numpy.core
import time:      1000 |       1300 |     numpy
import time:       200 |       1500 |   contact.layer.prandtl_layer
import time:        50 |         50 |     yaml
import time:       400 |        450 |   numba
import time:       100 |       2050 | contact.scenes.scene
import time:       500 |        500 | numba.np.arraymath
"""


def test_parse_importtime_depth_and_importer():
    recs = parse_importtime(SAMPLE)
    names = [r.name for r in recs]
    assert names == ["_io", "encodings", "numpy.core", "numpy", "contact.layer.prandtl_layer", "yaml", "numba",
                     "contact.scenes.scene", "numba.np.arraymath"]
    by = {r.name: r for r in recs}
    assert [by[n].depth for n in ("numpy.core", "numpy", "contact.layer.prandtl_layer", "contact.scenes.scene")] \
        == [3, 2, 1, 0]
    assert (by["numpy.core"].self_us, by["numpy.core"].cumulative_us) == (300, 300)

    def parent(n):
        p = by[n].parent
        return None if p < 0 else recs[p].name

    assert parent("_io") == "encodings"
    assert parent("numpy.core") == "numpy"
    assert parent("numpy") == "contact.layer.prandtl_layer"
    assert parent("yaml") == "numba"
    assert parent("numba") == "contact.scenes.scene"
    assert parent("contact.scenes.scene") is None and parent("numba.np.arraymath") is None


def test_import_seconds_sums_top_level_cumulative_without_the_bare_interpreter():
    recs = parse_importtime(SAMPLE)
    assert import_seconds(recs) == pytest.approx((1403 + 2050 + 500) / 1e6)
    assert import_seconds(recs, frozenset({"encodings"})) == pytest.approx((2050 + 500) / 1e6)
    assert import_seconds(parse_importtime("no importtime output\n")) == 0.0


def test_groups_sum_self_times_and_name_the_importer_of_their_heaviest_entry():
    assert group_of("numba.np.arraymath") == "numba"
    assert group_of("contact.layer.prandtl_layer") == "contact.layer"
    assert group_of("wrlayer") == "wrlayer"
    groups = {g.group: g for g in import_groups(parse_importtime(SAMPLE))}
    assert groups["numba"].self_s == pytest.approx(900 / 1e6) and groups["numba"].modules == 2
    # entries of numba: numba (450 us, by contact.scenes.scene) and numba.np.arraymath (500 us, at run time)
    assert groups["numba"].importer == "(run time)" and groups["numba"].project_importer == ""
    assert groups["numpy"].self_s == pytest.approx(1300 / 1e6)
    assert groups["numpy"].importer == "contact.layer.prandtl_layer"
    assert groups["numpy"].project_importer == "contact.layer.prandtl_layer"
    assert groups["yaml"].importer == "numba" and groups["yaml"].project_importer == "contact.scenes.scene"
    assert groups["contact.scenes"].importer == "(run time)" and groups["contact.scenes"].project_importer == ""
    ordered = [g.group for g in import_groups(parse_importtime(SAMPLE))]
    assert ordered[0] == "numpy"  # heaviest first


def test_module_level_importers_reads_the_module_body_only(tmp_path):
    pkg = tmp_path / "contact"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "eager.py").write_text("import numba\nfrom scipy import sparse\n")
    (pkg / "guarded.py").write_text("try:\n    import numba.core\nexcept ImportError:\n    numba = None\n")
    (pkg / "lazy.py").write_text("def f():\n    import numba\n    return numba\n")
    found = module_level_importers(tmp_path, {"numba", "scipy"})
    assert found == {"numba": ["contact.eager", "contact.guarded"], "scipy": ["contact.eager"]}
    assert module_level_importers(tmp_path, {"numba"}, {"contact.guarded"}) == {"numba": ["contact.guarded"]}


def test_lazy_library_imports_are_the_top_level_third_party_ones():
    # numba.np.arraymath at depth 0: imported by numba itself at run time; encodings is the standard library
    assert lazy_library_seconds(parse_importtime(SAMPLE)) == pytest.approx(500 / 1e6)
