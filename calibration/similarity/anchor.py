"""Similarity anchored to a direct FEM: a position of a worn profile from the master, corrected by the master's own
error at the same position of the profile the direct FEM calibrated (units mm, MPa).

The master's error at a position is mostly a property of the body around it, not of the patch: its first-yield
pressure p_y is 0.2-1.6 % off the direct FEM where the section is not the master's arc (the gauge side of the rail
head, the wheel's rim), and u_pl at equal p0 moves about ten times as much (``docs/validation/similarity.md``).
That error changes slowly as a profile wears, so a worn position takes the master's value plus the master's error
at the same y of the reference profile (the one its direct FEM table was calibrated on), in the master's
dimensionless variables (:mod:`calibration.similarity.master`):

    p_y(worn) = p_y,m(worn) p_y,d(ref) / p_y,m(ref)
    u_pl(q p_y) / L = U_m(worn; q) + [U_d(ref; q) - U_m(ref; q)]          (q = p0 / p_y)
    residual(f p_y) / L = R_m(worn; f) + [R_d(ref; f) - R_m(ref; f)]     (f: the unloading peaks)
    c_el = c_el,m(worn) c_el,d(ref) / c_el,m(ref)

(m: the master at the position's semi-axes and convexity; d: the direct FEM; L = sqrt(a b) of each). On the
reference profile itself the anchored value is the direct FEM's at the master's levels.

The master's error depends on the patch as well as on the body, so a position is anchored only while its patch
stays within about one master grid cell of the reference's (:func:`applies` with :data:`ANCHOR_LIMITS`: convexity
within 0.03, a/b and sqrt(a b) within the factors 2 and 1.5; the grid steps are 0.05-0.07, x1.82 and x2.17).
Measured on the wear example's profiles after 3000 km and with that wear x5 (``docs/validation/similarity-worn.md``):
anchoring everywhere helps after 3000 km and hurts where the patch changed shape (b 5.4 -> 1.2 mm at rail -25 mm with
the wear x5: 1.6 % -> 10 %).
The wear loop's recalibration by similarity anchors the positions its scene's direct table holds
(:mod:`contact.wear.recalibrate`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from calibration.results import IndentationResult
from calibration.similarity.master import MasterCurves
from calibration.similarity.route import similar_indentation
from calibration.similarity.sections import patch_convexity, plastic_convexity
from meshes.profiles import Profile, get_profile
from wrlayer.errors import InputError
from wrlayer.layer_table import LayerTable


@dataclass(frozen=True)
class PatchLimits:
    """How far a position's patch may be from a reference's for the reference to stand for it: ``convexity``, the
    largest change of the surface convexity b / (2 R) (-); ``aspect_factor`` and ``size_factor``, the largest
    factors between the aspect ratios a/b and between the patch sizes sqrt(a b) (-)."""

    convexity: float
    aspect_factor: float
    size_factor: float


#: The patch a reference anchors (about one master grid cell; see the module).
ANCHOR_LIMITS = PatchLimits(convexity=0.03, aspect_factor=2.0, size_factor=1.5)


@dataclass(frozen=True)
class DirectReference:
    """The direct FEM of one position of a reference profile (a direct table's entry), anchoring the similarity
    results of the same position on other profiles.

    Attributes
    ----------
    body : str
        "wheel" or "rail".
    y_mm : float
        Lateral position on the profile (mm).
    a_mm, b_mm : float
        Semi-axes of the calibrated patch (mm).
    convexity : float
        Surface convexity b / (2 R) of the reference profile over the patch (-).
    p_y_MPa : float
        FEM first-yield pressure (MPa).
    p_MPa, u_pl_mm : tuple of float
        The FEM loading curve: p0 (MPa) and u_pl (mm).
    peaks_MPa, residual_mm : tuple of float
        Unloading peaks (MPa) and the FEM residual dents after them (mm).
    compliance_mm_per_MPa : float
        The FEM mesh's elastic centre compliance (mm/MPa).
    source : str
        Where the entry comes from (a table file), for the entry's notes.
    plastic_convexity : float or None
        The convexity of the reference profile the plastic curves are taken at
        (:func:`calibration.similarity.sections.plastic_convexity`; None: ``convexity``) (-).
    kind : str
        What the reference's numbers are, for the notes: "direct FEM", or "section's elastic solve" (a served
        position whose p_y and c_el came from its own section: its curves are the master's at those, so it anchors
        p_y and c_el only; :func:`calibration.similarity.elastic.section_reference`).
    """

    body: str
    y_mm: float
    a_mm: float
    b_mm: float
    convexity: float
    p_y_MPa: float
    p_MPa: tuple[float, ...]
    u_pl_mm: tuple[float, ...]
    peaks_MPa: tuple[float, ...]
    residual_mm: tuple[float, ...]
    compliance_mm_per_MPa: float
    source: str = ""
    plastic_convexity: float | None = None
    kind: str = "direct FEM"

    @property
    def length_mm(self) -> float:
        """Patch size sqrt(a b) (mm)."""
        return math.sqrt(self.a_mm * self.b_mm)


def patch_moved(ref: DirectReference, a_mm: float, b_mm: float, convexity: float, limits: PatchLimits) -> str:
    """How the patch a x b (mm) on a surface of convexity ``convexity`` (-) differs from ``ref``'s when it lies
    beyond ``limits`` of it ("the patch (...) is not the reference's (...)"), "" when within."""
    aspect = abs(math.log((a_mm / b_mm) / (ref.a_mm / ref.b_mm)))
    size = abs(math.log(math.sqrt(a_mm * b_mm) / ref.length_mm))
    if abs(convexity - ref.convexity) > limits.convexity or aspect > math.log(limits.aspect_factor) \
            or size > math.log(limits.size_factor):
        return (f"the patch (a/b {a_mm / b_mm:.3g}, sqrt(ab) {math.sqrt(a_mm * b_mm):.3g} mm, b/(2R) "
                f"{convexity:+.3f}) is not the reference's (a/b {ref.a_mm / ref.b_mm:.3g}, sqrt(ab) "
                f"{ref.length_mm:.3g} mm, b/(2R) {ref.convexity:+.3f})")
    return ""


def applies(ref: DirectReference, a_mm: float, b_mm: float, convexity: float) -> str:
    """Why ``ref`` does not anchor the patch a x b (mm) on a surface of convexity ``convexity`` (-), or "" when it
    does (the patch within :data:`ANCHOR_LIMITS` of the reference's)."""
    moved = patch_moved(ref, a_mm, b_mm, convexity, ANCHOR_LIMITS)
    return f"not anchored: {moved}" if moved else ""


def reference_of_entry(body: str, entry: dict, convexity: float, source: str,
                       plastic_convexity: float | None = None) -> DirectReference | None:
    """The :class:`DirectReference` of a layer table's position entry (as :class:`wrlayer.layer_table.LayerTable`
    reads it), or None when the entry holds no direct 3D FEM (a similarity entry, a 2D or an older table).
    InputError naming the entry when its FEM fields are malformed."""
    fem, geo = entry.get("fem"), entry.get("geometry")
    if entry.get("method", "direct") != "direct" or not isinstance(fem, dict) or not isinstance(geo, dict) \
            or fem.get("model") != "3d" or "residual_fem_mm" not in entry:
        return None
    where = f"{source}: position y = {entry.get('y_mm')} mm"
    try:
        ref = DirectReference(body, float(entry["y_mm"]), float(geo["a_mm"]), float(geo["b_mm"]), float(convexity),
                              float(entry["first_yield_fem_MPa"]), tuple(map(float, fem["p_MPa"])),
                              tuple(map(float, fem["u_pl_mm"])), tuple(map(float, entry["residual_peaks_MPa"])),
                              tuple(map(float, entry["residual_fem_mm"])),
                              float(fem["fem_elastic_compliance_mm_per_MPa"]), source, plastic_convexity)
    except (KeyError, TypeError, ValueError) as err:
        raise InputError(where, f"its direct FEM fields cannot anchor a similarity result ({err!r})") from None
    numbers = (ref.a_mm, ref.b_mm, ref.p_y_MPa, ref.compliance_mm_per_MPa)
    if not all(math.isfinite(v) and v > 0 for v in numbers) or len(ref.p_MPa) != len(ref.u_pl_mm) \
            or len(ref.peaks_MPa) != len(ref.residual_mm):
        raise InputError(where, "its direct FEM fields cannot anchor a similarity result (non-positive sizes or "
                                "curves of unequal lengths)")
    return ref


def table_references(table: LayerTable, profile: Profile) -> dict[tuple[str, float], DirectReference]:
    """{(body, y): :class:`DirectReference`} of the direct 3D FEM entries of ``table``, calibrated on
    ``profile`` (its convexity over each patch, :func:`calibration.similarity.sections.patch_convexity`)."""
    out = {}
    for entry in table.positions:
        geo = entry.get("geometry")
        if not isinstance(geo, dict) or "b_mm" not in geo:
            continue
        y, b = float(entry["y_mm"]), float(geo["b_mm"])
        ref = reference_of_entry(table.body, entry, patch_convexity(profile, y, b), table.source,
                                 plastic_convexity(profile, y, b))
        if ref is not None:
            out[ref.body, ref.y_mm] = ref
    return out


def table_profile(table: LayerTable) -> Profile:
    """The profile a table was calibrated on, as its header names it (``profile_source``: a builtin name or a
    file); InputError when it cannot be read."""
    return get_profile(table.header.get("profile_source") or table.profile_name)


def configured_references(bodies) -> dict[tuple[str, float], DirectReference]:
    """The references of the bodies' ``anchor_table`` (:class:`calibration.settings.BodySettings`), each table on
    the profile it was calibrated on (:func:`table_profile`)."""
    out = {}
    for b in bodies:
        if b.anchor_table:
            table = LayerTable.read(b.anchor_table)
            out.update(table_references(table, table_profile(table)))
    return out


@dataclass(frozen=True)
class Anchor:
    """The master's error at one position of the reference profile, dimensionless (see the module): ``p_y_ratio``
    and ``compliance_ratio`` (direct / master, -), ``u_pl`` (U_d - U_m at the master's levels q, -) and
    ``residual`` (R_d - R_m at the master's unloading peaks, -)."""

    p_y_ratio: float
    compliance_ratio: float
    u_pl: tuple[float, ...]
    residual: tuple[float, ...]
    source: str


def anchor(master: MasterCurves, ref: DirectReference) -> Anchor:
    """The master's error at ``ref`` (the master evaluated at the reference's semi-axes and convexity)."""
    base = similar_indentation(master, ref.a_mm, ref.b_mm, ref.convexity, ref.plastic_convexity)
    q, f = np.asarray(master.q), np.asarray(master.unload_factors)
    length = ref.length_mm
    u_direct = np.interp(q * ref.p_y_MPa, ref.p_MPa, ref.u_pl_mm) / length
    du = u_direct - np.asarray(base.u_pl_mm) / length
    if ref.peaks_MPa:
        r_direct = np.interp(f * ref.p_y_MPa, ref.peaks_MPa, ref.residual_mm) / length
        dr = r_direct - np.asarray(base.residual_fem_mm) / length
    else:  # a table without unloading: the residuals keep the master's
        dr = np.zeros(f.size)
    return Anchor(ref.p_y_MPa / base.first_yield_MPa,
                  ref.compliance_mm_per_MPa / base.fem_elastic_compliance_mm_per_MPa,
                  tuple(du.tolist()), tuple(dr.tolist()), ref.source)


def anchored(sim: IndentationResult, anc: Anchor, length_mm: float) -> IndentationResult:
    """The master's result ``sim`` (:func:`calibration.similarity.route.similar_indentation`, patch size
    ``length_mm`` = sqrt(a b) in mm) corrected by ``anc``; u_pl and the residuals stay non-negative and
    non-decreasing (a correction larger than the worn value near first yield is cut at zero)."""
    p_y = sim.first_yield_MPa * anc.p_y_ratio
    p = np.asarray(sim.p_MPa) * anc.p_y_ratio
    u_pl = np.maximum.accumulate(np.maximum(np.asarray(sim.u_pl_mm) + np.asarray(anc.u_pl) * length_mm, 0.0))
    peaks = np.asarray(sim.unload_peaks_MPa) * anc.p_y_ratio
    residual = np.maximum.accumulate(np.maximum(np.asarray(sim.residual_fem_mm)
                                                + np.asarray(anc.residual) * length_mm, 0.0))
    c_el = sim.fem_elastic_compliance_mm_per_MPa * anc.compliance_ratio
    return replace(sim, p_MPa=p.tolist(), u_fem_mm=(c_el * p + u_pl).tolist(), u_pl_mm=u_pl.tolist(),
                   first_yield_MPa=p_y, first_yield_anywhere_MPa=p_y, fem_elastic_compliance_mm_per_MPa=c_el,
                   unload_peaks_MPa=peaks.tolist(), residual_fem_mm=residual.tolist(),
                   reverse_plasticity_mm=(residual - np.interp(peaks, p, u_pl)).tolist())


__all__ = ["ANCHOR_LIMITS", "Anchor", "DirectReference", "PatchLimits", "anchor", "anchored", "applies",
           "configured_references", "patch_moved", "table_profile", "reference_of_entry", "table_references"]
