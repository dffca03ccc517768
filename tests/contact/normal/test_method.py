"""solve_normal_with: problem, then layer, then the method as keyword; clear errors for wrong types; the default
("auto") is the exact solver."""


import pytest

from contact.layer.prandtl_layer import LayerPair
from contact.normal.method import NormalMethod, solve_normal_with
from contact.normal.kik_piotrowski import solve_normal
from contact.scenes.paper_example import paper_layers, paper_problem


@pytest.fixture(scope="module")
def prob():
    return paper_problem()


def test_method_by_name_or_object_gives_the_same_solution(prob):
    layer = paper_layers(prob)
    ref = solve_normal(prob, layer)
    for method in ("kik_piotrowski", NormalMethod("kik_piotrowski")):
        sol = solve_normal_with(prob, layer, method=method)
        assert sol.delta_mm == ref.delta_mm and sol.p_max_MPa == ref.p_max_MPa
    default = solve_normal_with(prob, layer)
    assert default.method == "exact"
    assert default.delta_mm == solve_normal_with(prob, layer, method="auto").delta_mm


def test_only_kik_piotrowski_has_an_approximate_p_max():
    assert [NormalMethod(n).p_max_approximate for n in ("kik_piotrowski", "exact", "coarse_exact", "auto")] == [
        True, False, False, False]


def test_method_first_is_a_type_error_naming_the_order(prob):
    with pytest.raises(TypeError, match="the problem comes first and the method last"):
        solve_normal_with(NormalMethod(), prob, paper_layers(prob))


@pytest.mark.parametrize("call, message", [
    (lambda p, lay: solve_normal_with(lay, p), "first argument must be a NormalProblem, got LayerPair"),
    (lambda p, lay: solve_normal_with(p, lay.combined), r"wrap it: LayerPair\(combined=layer\)"),
    (lambda p, lay: solve_normal_with(p, lay, method=3), "method must be a NormalMethod"),
    (lambda p, lay: solve_normal_with(p, lay, NormalMethod()), "pass the method as method="),
    (lambda p, lay: solve_normal(lay, p), "solve_normal: the first argument must be a NormalProblem"),
])
def test_wrong_types_raise_type_errors_naming_the_argument(prob, call, message):
    with pytest.raises(TypeError, match=message):
        call(prob, paper_layers(prob))


def test_unknown_method_name_is_an_input_error(prob):
    from wrlayer.errors import InputError

    with pytest.raises(InputError, match="method.normal"):
        solve_normal_with(prob, LayerPair(), method="fem")


def test_solution_reprs_show_numbers_not_arrays(prob):
    sol = solve_normal_with(prob, paper_layers(prob), method="kik_piotrowski")
    for text in (repr(sol), repr(sol.regions[0]), repr(sol.patches[0]), repr(prob)):
        assert "array" not in text and len(text) < 300
    assert "delta=0.127109 mm" in repr(sol)
