"""The solver's error classes: what they mean, how the plain solver errors map onto them, their exit codes."""

import numpy as np
import pytest

from wrlayer.characteristic import Characteristic
from contact.scenes.layers import LayerSources
from contact.wheel_rail.inputs import WheelRailInputs
from contact.wheel_rail.solve import solve_wheel
from contact.wheel_rail.track_geometry import WheelsetPose
from wrlayer.errors import (
    ConvergenceError,
    InputError,
    LayerElementMissing,
    LayerNotCovered,
    PatchTruncated,
    cli_guard,
    typed_input_error,
)


@pytest.mark.parametrize("error, code", [
    (PatchTruncated("separation.y_mm", "the contact patch reaches the end"), 2),
    (LayerNotCovered("layers.rail (t.json)", "does not cover the contact location"), 2),
    (LayerElementMissing("rail layer (t.json)", "no element"), 2),
    (ConvergenceError("case: vertical load balance"), 3),
])
def test_subclasses_keep_the_documented_exit_codes(error, code, capsys):
    @cli_guard
    def main():
        raise error

    assert main() == code
    assert capsys.readouterr().err.strip() == f"error: {error}"


def test_plain_solver_errors_become_the_subclasses():
    truncated = typed_input_error(InputError("separation.y_mm", "the contact patch reaches the end of the table"))
    assert isinstance(truncated, PatchTruncated) and truncated.what == "separation.y_mm"
    missing = typed_input_error(InputError("rail layer (t.json)", "does not cover the contact patch (strips without "
                                                                   "a layer element)"))
    assert isinstance(missing, LayerElementMissing) and isinstance(missing, LayerNotCovered)
    other = InputError("load.normal_force_N", "must be > 0")
    assert typed_input_error(other) is other
    typed = PatchTruncated("x", "y")
    assert typed_input_error(typed) is typed


class NarrowTable:
    """A rail table covering only y in [5, 6] mm: the tread contact near y = 0 lies outside."""

    y_range_mm = (5.0, 6.0)
    rolling_law = None

    def characteristic_at(self, y_mm, patch_mm=None):
        return Characteristic(np.array([0.0, 0.01, 0.05]), np.array([0.0, 300.0, 900.0]))


def test_a_table_not_covering_a_loaded_strip_is_layer_not_covered(rail60, s1002, placed):
    layers = LayerSources(rail=NarrowTable(), names={"rail": "narrow.json"})
    with pytest.raises(LayerNotCovered, match=r"^layers.rail \(narrow.json\): does not cover the contact location"):
        solve_wheel(rail60, s1002, WheelRailInputs(pose=WheelsetPose(0.0)), layers, placed_rail=placed)
