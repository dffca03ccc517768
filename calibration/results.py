"""The results of one calibration position as frozen dataclasses: the FEM indentation and the fitted table entry.

Both are written as JSON only at the edge (the cache entries ``OUT/cache/*.json`` and the layer table's
``positions``) with ``to_dict``; ``from_dict`` validates every field (InputError naming it), so a cache entry of
the wrong shape is recognised and recomputed. Units: mm, MPa, N/mm^3, s.
"""

from __future__ import annotations

import math
from dataclasses import MISSING, asdict, dataclass, field, fields
from typing import Any

from calibration.hertz.geometry import LocalGeometry
from wrlayer import validate
from wrlayer.errors import InputError

#: IndentationResult fields by kind (the checks of from_dict); lists: their least length.
_IND_LISTS = {"p_MPa": 2, "u_fem_mm": 2, "u_pl_mm": 2, "unload_peaks_MPa": 0, "residual_fem_mm": 0,
              "reverse_plasticity_mm": 0, "u_centre_abs_mm": 0}
_IND_NUMBERS = ("first_yield_MPa", "first_yield_anywhere_MPa", "fem_elastic_compliance_mm_per_MPa",
                "halfspace_compliance_mm_per_MPa", "seconds", "output_seconds")
_IND_OPTIONAL_NUMBERS = ("reference_depth_mm", "fem_absolute_compliance_mm_per_MPa")
_IND_COUNTS = ("n_dofs", "n_elements", "newton_iterations", "linear_solves", "factorisations")


@dataclass(frozen=True)
class IndentationResult:
    """Raw FEM characteristic of one position (the FEM cache entry).

    Attributes
    ----------
    model : str
        "2d" or "3d".
    p_MPa : list of float
        Peak Hertz pressure p0 of every converged loading increment, from 0 (MPa).
    u_fem_mm : list of float
        Normal displacement of the load centre at p_MPa, into the body (mm).
    u_pl_mm : list of float
        Its inelastic part u_FEM - c_el p0 (mm).
    first_yield_MPa : float
        FEM first-yield pressure p_y near the contact (MPa).
    first_yield_anywhere_MPa : float
        The whole model's first-yield pressure (may be a structural stress concentration) (MPa).
    fem_elastic_compliance_mm_per_MPa : float
        Elastic compliance c_el of the load centre on the same mesh (mm/MPa).
    halfspace_compliance_mm_per_MPa : float
        Half-space centre compliance c_hs of the Hertz patch (mm/MPa).
    unload_peaks_MPa : list of float
        Peaks from which the FEM unloaded to zero (MPa).
    residual_fem_mm : list of float
        FEM residual dents after unloading from those peaks (mm).
    reverse_plasticity_mm : list of float
        Residual dent minus u_pl at the peak (mm).
    n_dofs : int
        Degrees of freedom of the FEM model.
    n_elements : int
        Elements of the FEM mesh.
    newton_iterations : int
        Newton iterations of the whole load path.
    seconds : float
        Wall time of the FEM: mesh and solves, without the field output (s).
    files : list of str
        VTK/PNG field files written.
    reference_depth_mm : float or None
        Depth of the reference material point (mm; None: against the clamped far field).
    u_centre_abs_mm : list of float
        Load-centre displacement against the clamped far field (mm).
    fem_absolute_compliance_mm_per_MPa : float or None
        Elastic compliance of the load centre against the far field (mm/MPa).
    u_pl_depth_mm : dict of list of float
        Inelastic displacements against further reference depths, by depth factor (mm).
    linear_solves : int
        Triangular solves of the kept factorisations (machine-independent cost).
    factorisations : int
        Factorisations.
    output_seconds : float
        Wall time of writing ``files`` (s).
    """

    model: str
    p_MPa: list[float]
    u_fem_mm: list[float]
    u_pl_mm: list[float]
    first_yield_MPa: float
    first_yield_anywhere_MPa: float
    fem_elastic_compliance_mm_per_MPa: float
    halfspace_compliance_mm_per_MPa: float
    unload_peaks_MPa: list[float]
    residual_fem_mm: list[float]
    reverse_plasticity_mm: list[float]
    n_dofs: int
    n_elements: int
    newton_iterations: int
    seconds: float
    files: list[str] = field(default_factory=list)
    reference_depth_mm: float | None = None
    u_centre_abs_mm: list[float] = field(default_factory=list)
    fem_absolute_compliance_mm_per_MPa: float | None = None
    u_pl_depth_mm: dict[str, list[float]] = field(default_factory=dict)
    linear_solves: int = 0
    factorisations: int = 0
    output_seconds: float = 0.0

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: Any, what: str = "indentation") -> IndentationResult:
        """Validate and build (InputError naming the field): every field present (those with defaults may be
        absent) with its type, lists flat and finite, p_MPa with >= 2 values, lengths consistent."""
        _check_fields(cls, data, what)
        kw: dict[str, Any] = {"model": validate.text(data["model"], validate.join(what, "model"))}
        for name, n in _IND_LISTS.items():
            if name in data:
                validate.number_list(data[name], validate.join(what, name), min_len=n)
                kw[name] = list(data[name])
        for name in _IND_COUNTS:
            if name in data:
                kw[name] = validate.integer(data[name], validate.join(what, name), ge=0)
        for name in _IND_NUMBERS + _IND_OPTIONAL_NUMBERS:
            if data.get(name) is not None or (name in data and name not in _IND_OPTIONAL_NUMBERS):
                validate.number(data[name], validate.join(what, name))
                kw[name] = data[name]
        if "files" in data:
            if not isinstance(data["files"], list) or not all(isinstance(v, str) for v in data["files"]):
                raise InputError(validate.join(what, "files"), "must be a list of file names")
            kw["files"] = list(data["files"])
        if "u_pl_depth_mm" in data:
            depth = validate.table(data["u_pl_depth_mm"], validate.join(what, "u_pl_depth_mm"))
            for name, item in depth.items():
                validate.number_list(item, validate.join(what, f"u_pl_depth_mm.{name}"), min_len=0)
            kw["u_pl_depth_mm"] = {k: list(v) for k, v in depth.items()}
        result = cls(**kw)
        result.check_consistent(what)
        return result

    def check_consistent(self, what: str) -> None:
        """InputError unless the lists agree in length and the half-space compliance is positive."""
        n = len(self.p_MPa)
        for name in ("u_fem_mm", "u_pl_mm"):
            if len(getattr(self, name)) != n:
                raise InputError(validate.join(what, name), f"has {len(getattr(self, name))} values, p_MPa has {n}")
        if len(self.residual_fem_mm) != len(self.unload_peaks_MPa):
            raise InputError(validate.join(what, "residual_fem_mm"), "length differs from unload_peaks_MPa")
        if not self.halfspace_compliance_mm_per_MPa > 0:
            raise InputError(validate.join(what, "halfspace_compliance_mm_per_MPa"), "must be > 0")


def _check_fields(cls, data: Any, what: str) -> None:
    """``data`` is a table with only ``cls``'s fields and all of its required ones."""
    validate.table(data, what)
    validate.check_known(data, [f.name for f in fields(cls)], what)
    for f in fields(cls):
        if f.default is MISSING and f.default_factory is MISSING and f.name not in data:
            raise InputError(validate.join(what, f.name), "missing")


@dataclass(frozen=True)
class FemSummary:
    """The FEM data kept in a layer-table position (``fem``); fields as in :class:`IndentationResult`.

    Attributes
    ----------
    model : str
        "2d" or "3d".
    p_MPa : list of float
        Peak pressures of the converged loading increments (MPa).
    u_fem_mm : list of float
        Load-centre displacement (mm).
    u_pl_mm : list of float
        Its inelastic part (mm).
    fem_elastic_compliance_mm_per_MPa : float
        Elastic compliance on the FEM mesh (mm/MPa).
    halfspace_compliance_mm_per_MPa : float
        Half-space centre compliance (mm/MPa).
    reverse_plasticity_mm : list of float
        Residual dent minus u_pl at each unloading peak (mm).
    n_dofs : int
        Degrees of freedom.
    n_elements : int
        Elements.
    newton_iterations : int
        Newton iterations.
    seconds : float
        FEM wall time without the field output (s).
    output_seconds : float
        Field output wall time (s).
    first_yield_anywhere_MPa : float
        The whole model's first-yield pressure (MPa).
    """

    model: str
    p_MPa: list[float]
    u_fem_mm: list[float]
    u_pl_mm: list[float]
    fem_elastic_compliance_mm_per_MPa: float
    halfspace_compliance_mm_per_MPa: float
    reverse_plasticity_mm: list[float]
    n_dofs: int
    n_elements: int
    newton_iterations: int
    seconds: float
    output_seconds: float
    first_yield_anywhere_MPa: float

    @classmethod
    def of(cls, ind: IndentationResult) -> FemSummary:
        return cls(**{f.name: getattr(ind, f.name) for f in fields(cls)})

    @classmethod
    def from_dict(cls, data: Any, what: str) -> FemSummary:
        _check_fields(cls, data, what)
        for name in ("p_MPa", "u_fem_mm", "u_pl_mm", "reverse_plasticity_mm"):
            validate.number_list(data[name], validate.join(what, name), min_len=0)
        for name in ("n_dofs", "n_elements", "newton_iterations"):
            validate.integer(data[name], validate.join(what, name), ge=0)
        for name in ("fem_elastic_compliance_mm_per_MPa", "halfspace_compliance_mm_per_MPa", "seconds",
                     "output_seconds", "first_yield_anywhere_MPa"):
            validate.number(data[name], validate.join(what, name))
        validate.text(data["model"], validate.join(what, "model"))
        return cls(**data)


@dataclass(frozen=True)
class PositionFit:
    """One position of a layer table (``positions[i]`` of ``<body>_layer_table.json``; the fit cache entry).

    Attributes
    ----------
    y_mm : float
        Lateral position on the profile (mm).
    characteristic : dict
        The fitted characteristic, ``{"u_mm": [...], "p_MPa": [...]}`` (mm, MPa; paper Fig. 2).
    n_segments : int
        Segments N of the characteristic.
    k_N_per_mm3 : list of float
        Prandtl element stiffnesses k_i (N/mm^3; eqs. 4-6).
    T0_MPa : list of float
        Prandtl element slip pressures T_0i (MPa; eqs. 4-6).
    slopes_N_per_mm3 : list of float
        Slopes S_i of the characteristic (N/mm^3).
    p2_MPa : float
        Elastic limit p_2 of the characteristic (MPa).
    first_yield_fem_MPa : float
        FEM first-yield pressure p_y (MPa).
    max_error_mm : float
        Largest fit error at the FEM points (mm).
    rms_error_mm : float
        RMS fit error (mm).
    residual_peaks_MPa : list of float
        Unloading peaks (MPa).
    residual_fit_mm : list of float
        Residual dents of the fit after unloading from them (mm; eq. 8).
    residual_fem_mm : list of float
        FEM residual dents (mm).
    residual_error_mm : list of float
        residual_fit_mm - residual_fem_mm (mm).
    geometry : LocalGeometry
        The position's contact geometry (mm, 1/mm, N, MPa).
    fem : FemSummary
        The FEM data of the position.
    fem_points : dict
        The fitted points ``{"p_MPa": [...], "u_mm": [...]}``, u = p / S_1 + u_pl (MPa, mm).
    fit_mode : str
        "operating_range" or "paper" (:class:`calibration.settings.FitSettings`).
    calibrated_max_MPa : float or None
        The largest pressure of the FEM load path (MPa): the table's calibrated range at this position.
    levels_over_p2 : list of float
        The FEM loading levels p0 / p_2 at and above first yield (-; "operating_range").
    u_pl_error : list of float
        (fit - FEM) u_pl at those levels over max(u_pl, u_pl(1.5 p_2) / 3) (-; "operating_range").
    residual_error : list of float
        (element - FEM) residual dent at the unloading peaks over max(dent, dent(1.5 p_2) / 3) (-;
        "operating_range").
    """

    y_mm: float
    characteristic: dict[str, list[float]]
    n_segments: int
    k_N_per_mm3: list[float]
    T0_MPa: list[float]
    slopes_N_per_mm3: list[float]
    p2_MPa: float
    first_yield_fem_MPa: float
    max_error_mm: float
    rms_error_mm: float
    residual_peaks_MPa: list[float]
    residual_fit_mm: list[float]
    residual_fem_mm: list[float]
    residual_error_mm: list[float]
    geometry: LocalGeometry
    fem: FemSummary
    fem_points: dict[str, list[float]]
    fit_mode: str = "paper"
    calibrated_max_MPa: float | None = None
    levels_over_p2: list[float] = field(default_factory=list)
    u_pl_error: list[float] = field(default_factory=list)
    residual_error: list[float] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_dict(cls, data: Any, what: str = "position") -> PositionFit:
        """Validate and build (InputError naming the field); the characteristic itself is checked by the layer
        table that holds the position."""
        _check_fields(cls, data, what)
        for name in ("y_mm", "p2_MPa", "first_yield_fem_MPa", "max_error_mm", "rms_error_mm"):
            validate.number(data[name], validate.join(what, name))
        validate.integer(data["n_segments"], validate.join(what, "n_segments"), ge=1)
        for name in ("k_N_per_mm3", "T0_MPa", "slopes_N_per_mm3", "residual_peaks_MPa", "residual_fit_mm",
                     "residual_fem_mm", "residual_error_mm", "levels_over_p2", "u_pl_error", "residual_error"):
            if name in data:
                validate.number_list(data[name], validate.join(what, name), min_len=0)
        if "fit_mode" in data:
            validate.text(data["fit_mode"], validate.join(what, "fit_mode"), ("operating_range", "paper"))
        if data.get("calibrated_max_MPa") is not None:
            validate.number(data["calibrated_max_MPa"], validate.join(what, "calibrated_max_MPa"), gt=0.0)
        points = validate.table(data["fem_points"], validate.join(what, "fem_points"))
        for name in ("p_MPa", "u_mm"):
            validate.number_list(points.get(name), validate.join(what, f"fem_points.{name}"), min_len=1)
        validate.table(data["characteristic"], validate.join(what, "characteristic"))
        kw = dict(data)
        kw["geometry"] = LocalGeometry.from_dict(data["geometry"], validate.join(what, "geometry"))
        kw["fem"] = FemSummary.from_dict(data["fem"], validate.join(what, "fem"))
        return cls(**kw)

    def check_position(self, y_mm: float, what: str) -> None:
        """InputError unless this is the fit of position ``y_mm``."""
        if not math.isclose(float(self.y_mm), float(y_mm), rel_tol=0, abs_tol=1e-9):
            raise InputError(validate.join(what, "y_mm"), f"is {self.y_mm!r}, expected {y_mm!r}")


__all__ = ["FemSummary", "IndentationResult", "PositionFit"]
