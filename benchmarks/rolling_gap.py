"""The gap between the layer's passes and the rolling FEM, and the rolling law that closes it (units mm, MPa).

Input: the cases of :mod:`benchmarks.rolling_gap_cases` (the FEM groove after every pass at constant p0). For
each case the layer's static residual r is the element's exact residual (paper eq. 8) of the calibrated characteristic at
the same p0 / p_2: the shipped table's characteristic at the position (p_2 its FEM first yield), or, for the
half-space, the characteristic fitted with the calibration's default fit to the block's static indentation at
the highest level (:func:`calibration.rolling.layer_prediction.layer_grooves`; on the finest mesh of
:mod:`benchmarks.rolling_gap_static` when given). The layer's groove after pass n is then
n r ("relaxed"), r ("state kept") and r G_n ("rolling", :class:`wrlayer.rolling_law.RollingLaw`).

The law of a group of positions (the rail table's, the wheel table's, the half-space's) is fitted
(:mod:`calibration.rolling.law_fit`) to the mean over the group's positions of the FEM groove over the block's
static dent, per level and traction. Two errors are reported per case: the law on the block's own static dent
(s G_n against the FEM groove: what the law reproduces) and the law on the layer (r G_n: what the contact code
gets, including the difference between the coarse block's static dent and the calibrated residual).
"""

from __future__ import annotations

import json
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from benchmarks.rolling_gap_cases import LEVELS, ROOT, TRACTIONS, GapCaseResult, default_positions
from calibration.rolling.layer_prediction import StaticCurve, layer_grooves
from calibration.rolling.law_fit import PassFit, fit_passes, rolling_law
from calibration.settings import FitSettings
from wrlayer.layer_table import LayerTable
from wrlayer.rolling_law import RollingLaw

#: The passes of the gap table.
REPORTED_PASSES = (1, 2, 5, 10)
#: Fewest FEM passes of a case in the gap table (below the reported 10, the case's own fit extrapolates, stated).
MIN_FEM_PASSES = 5
#: The target: the layer's accumulated residual within this fraction of the FEM groove.
TARGET = 0.10
#: Stand-ins: a position whose own cases are missing is represented by another position's cases of the same
#: material and patch shape (a/b within 0.3 %), grooves and dents scaled by the ratio of the semi-axes a (at equal
#: p0 / p_y and a/b the solution has no length of its own: docs/calibration.md).
STAND_INS = {"wheel tread": "rail crown", "wheel flange root": "rail gauge corner"}
#: The law groups: name -> the positions whose mean it is fitted to (and the table it is written into).
GROUPS = {"rail": (("rail crown", "rail gauge corner"), "scenes/tables/rail_60E1_default.json"),
          "wheel": (("wheel flange root", "wheel tread"), "scenes/tables/wheel_S1002_default.json"),
          "half-space": (("half-space",), ""),
          "long patch": (("rail field side",), ""),
          "very long patch": (("rail field shoulder",), "")}
#: The groups whose laws are every table's further patch-shape nodes (:func:`shaped_law`): blocks at the long
#: patches of the rail's field side (a/b = 3.83) and shoulder (10.2); the tables' own groups are round (a/b =
#: 1.33-1.35).
LONG_PATCHES = ("long patch", "very long patch")
#: The tables' nodes still fitted to blocks and written by :func:`write_block_nodes` (no section has that patch).
BLOCK_NODES = ("very long patch",)
#: The half-space layer's fit: the calibration's default (its number of segments; p_2 = the block's p_y).
LAYER_FIT = FitSettings()


@dataclass(frozen=True)
class GapRow:
    """One case of the gap table (lists: one entry per pass of ``passes``).

    Attributes
    ----------
    position : str
        Name of the position.
    group : str
        The law's group (rail, wheel, half-space).
    traction : float
        Traction coefficient c (-).
    p0_over_py : float
        Peak pressure over p_y (-; the block's p_y for the FEM, the table's p_2 for the layer).
    p0_MPa : float
        Peak pressure of the FEM (MPa).
    static_dent_mm : float
        The block's static dent (mm).
    layer_static_mm : float
        The layer's static residual r (the element's exact unloading) at the same p0 / p_2 (mm).
    passes : list of int
        The passes reported.
    fem_mm : list of float
        FEM groove after those passes (mm).
    relaxed_mm : list of float
        Layer, "relaxed": n r (mm).
    state_kept_mm : list of float
        Layer, "state kept": r (mm).
    rolling_mm : list of float
        Layer, "rolling": r G_n (mm).
    law_on_block_mm : list of float
        The law on the block's static dent: s G_n (mm).
    fem_passes : int
        Passes the FEM computed; the FEM groove of later passes is this case's own law fit extrapolated.
    key : str
        The case (with its stand-in, if any).
    """

    position: str
    group: str
    traction: float
    p0_over_py: float
    p0_MPa: float
    static_dent_mm: float
    layer_static_mm: float
    passes: list[int]
    fem_mm: list[float]
    relaxed_mm: list[float]
    state_kept_mm: list[float]
    rolling_mm: list[float]
    law_on_block_mm: list[float]
    fem_passes: int
    key: str

    def error(self, name: str) -> float:
        """The largest |layer / FEM - 1| over the passes for the layer column ``name`` (-)."""
        return float(np.max(np.abs(np.asarray(getattr(self, name)) / np.asarray(self.fem_mm) - 1.0)))

    def to_dict(self) -> dict:
        out = {k: getattr(self, k) for k in self.__dataclass_fields__}
        out.update({f"error_{k}": self.error(k) for k in ("relaxed_mm", "state_kept_mm", "rolling_mm",
                                                          "law_on_block_mm")})
        return out


def load_results(out_dir: Path) -> list[GapCaseResult]:
    """The case files of ``out_dir`` (each ``<key>.json``)."""
    return [GapCaseResult.from_dict(json.loads(p.read_text())) for p in sorted(Path(out_dir).glob("*_c*_p*.json"))]


def with_stand_ins(results: list[GapCaseResult]) -> list[GapCaseResult]:
    """``results`` plus, for every stand-in position without its own case, the stand-in's case scaled to it
    (key suffixed " (stand-in: <position>)"). The table positions come from
    :func:`benchmarks.rolling_gap_cases.default_positions`."""
    have = {(r.position, r.traction, r.p0_over_py) for r in results if r.complete}
    targets = {p.name: p for p in default_positions()}
    out = list(results)
    for r in results:
        for name, proxy in STAND_INS.items():
            if r.position != proxy or (name, r.traction, r.p0_over_py) in have:
                continue
            pos = targets[name]
            k = pos.a_mm / r.a_mm
            out.append(replace(r, key=f"{r.key} (stand-in: {proxy})", position=name, table=pos.table, y_mm=pos.y_mm,
                               a_mm=pos.a_mm, b_mm=pos.b_mm, static_dent_mm=k * r.static_dent_mm,
                               static_u_pl_mm=[k * u for u in r.static_u_pl_mm],
                               groove_mm=[k * g for g in r.groove_mm], shift_mm=[k * g for g in r.shift_mm]))
    return out


def group_of(position: str) -> str:
    return next(name for name, (members, _) in GROUPS.items() if position in members)


@dataclass(frozen=True)
class HalfspaceStatic:
    """The half-space block's static indentation its layer is fitted to (mm, MPa).

    Attributes
    ----------
    curve : StaticCurve
        The highest level's loading curve.
    p_y_MPa : float
        The block's FEM first-yield pressure (MPa).
    levels : tuple of float
        Peak pressures over p_y of the static dents (-).
    dents_mm : tuple of float
        The residual dent after load and unload at each level (mm).
    """

    curve: StaticCurve
    p_y_MPa: float
    levels: tuple[float, ...]
    dents_mm: tuple[float, ...]

    @classmethod
    def of_cases(cls, mine: list[GapCaseResult]) -> HalfspaceStatic:
        """From the cases themselves: the loading points of every case's static indentation together (one virgin
        load path, so one curve; each level adds its own peak, which the highest level's steps of p_y / 10 miss
        near first yield, where u_pl is most curved) and every level's static dent (the cases of one level share
        it)."""
        points = {round(p, 9): u for r in mine for p, u in zip(r.static_p_MPa, r.static_u_pl_mm)}
        p = np.array(sorted(points))
        top = max(mine, key=lambda r: r.p0_over_py)
        dents = {r.p0_over_py: r.static_dent_mm for r in mine}
        levels = tuple(sorted(dents))
        curve = StaticCurve(p, np.array([points[k] for k in p]), top.static_dent_mm)
        return cls(curve, top.p_y_MPa, levels, tuple(dents[lv] for lv in levels))


def layer_static_residuals(results: list[GapCaseResult],
                           halfspace: HalfspaceStatic | None = None) -> dict[tuple[str, float], float]:
    """The layer's static residual r (mm) per (position, p0 / p_y): the table's characteristic at the position
    (p0 = level x its p_2), or for the half-space the characteristic fitted as the calibration fits (``LAYER_FIT``,
    :func:`calibration.rolling.layer_prediction.layer_grooves`: the loaded curve and the residual dent at every
    level) to ``halfspace`` (the finest mesh of :mod:`benchmarks.rolling_gap_static`) when given, else to the
    cases' own (coarse) static indentations."""
    out = {}
    for pos in {r.position for r in results}:
        mine = [r for r in results if r.position == pos]
        if mine[0].table:
            ch = LayerTable.read(ROOT / mine[0].table).characteristic_at(mine[0].y_mm)
            for lv in {r.p0_over_py for r in mine}:
                out[(pos, lv)] = float(ch.unloading_residual(lv * ch.elastic_limit_MPa))
            continue
        ref = halfspace if halfspace is not None else HalfspaceStatic.of_cases(mine)
        levels = sorted({r.p0_over_py for r in mine})
        grooves = layer_grooves(ref.curve, ref.p_y_MPa, [lv * ref.p_y_MPa for lv in levels], 1,
                                LAYER_FIT.max_segments, list(ref.dents_mm),
                                [lv * ref.p_y_MPa for lv in ref.levels])
        out.update({(pos, lv): g.relaxed[0] for lv, g in zip(levels, grooves)})
    return out


def fit_group(results: list[GapCaseResult], group: str) -> tuple[RollingLaw, dict]:
    """The group's law from the mean normalised groove of its positions, and the fits {(c, level): PassFit}."""
    members, _ = GROUPS[group]
    mine = [r for r in results if r.position in members and len(r.groove_mm) >= MIN_FEM_PASSES]
    fits: dict[tuple[float, float], PassFit] = {}
    for c in TRACTIONS:
        for lv in LEVELS:
            cases = [r for r in mine if r.traction == c and r.p0_over_py == lv]
            if not cases:
                continue
            n = min(len(r.groove_mm) for r in cases)
            mean = np.mean([np.asarray(r.groove_mm[:n]) / r.static_dent_mm for r in cases], axis=0)
            fits[(c, lv)] = fit_passes(mean, 1.0)
    tractions = [c for c in TRACTIONS if all((c, lv) in fits for lv in LEVELS)]
    if not tractions:
        raise KeyError(f"{group}: no traction with all levels computed")
    passes = min(len(r.groove_mm) for r in mine)
    source = (f"rolling FEM of {', '.join(members)} (benchmarks.rolling_gap_cases: h = a/2 quadratic tetrahedra, "
              f"step a/4, track 1.5 contact lengths, {passes} passes at constant p0)")
    return rolling_law(list(LEVELS), tractions, fits, source), fits


def gap_rows(results: list[GapCaseResult],
             halfspace: HalfspaceStatic | None = None) -> tuple[list[GapRow], dict[str, RollingLaw]]:
    """The gap table's rows (cases with at least MIN_FEM_PASSES passes) and the laws of the groups; the half-space
    layer as in :func:`layer_static_residuals`."""
    laws = {}
    for g in GROUPS:
        try:
            laws[g] = fit_group(results, g)[0]
        except (KeyError, ValueError, IndexError):  # a group without a complete grid yet: no law
            continue
    statics = layer_static_residuals(results, halfspace)
    rows = []
    n = np.array(REPORTED_PASSES)
    for r in results:
        g = group_of(r.position)
        if len(r.groove_mm) < MIN_FEM_PASSES or g not in laws:
            continue
        own = fit_passes(r.groove_mm, r.static_dent_mm).factors(int(n.max())) * r.static_dent_mm
        fem = [r.groove_mm[k - 1] if k <= len(r.groove_mm) else float(own[k - 1]) for k in n]
        rs = statics[(r.position, r.p0_over_py)]
        fac = laws[g].factor(n, r.p0_over_py, r.traction)
        rows.append(GapRow(r.position, g, r.traction, r.p0_over_py, r.p0_over_py * r.p_y_MPa, r.static_dent_mm, rs,
                           n.tolist(), fem, (rs * n).tolist(), [rs] * n.size, (rs * fac).tolist(),
                           (r.static_dent_mm * fac).tolist(), len(r.groove_mm), r.key))
    return rows, laws


def group_aspect_ratios() -> dict[str, float]:
    """The patch shape a/b of every law group (-): the geometric mean over its positions' Hertz patches (the
    positions read once)."""
    shapes = {p.name: p.a_mm / p.b_mm for p in default_positions()}
    return {g: float(np.exp(np.mean(np.log([shapes[m] for m in members])))) for g, (members, _) in GROUPS.items()}


def group_aspect_ratio(group: str) -> float:
    """The patch shape a/b of the law group ``group`` (-; :func:`group_aspect_ratios`)."""
    return group_aspect_ratios()[group]


def shaped_law(group: str, laws: dict[str, RollingLaw]) -> RollingLaw:
    """The law written into the table of ``group``: its own law (fitted here, or the one the table holds when the
    group's cases are absent) at the group's patch shape and the :data:`LONG_PATCHES` laws at theirs
    (:meth:`RollingLaw.by_aspect`; KeyError when a long-patch law or a law for the group is missing)."""
    own = laws.get(group)
    if own is None:
        stored = LayerTable.read(ROOT / GROUPS[group][1]).rolling_law
        if stored is None:
            raise KeyError(f"{group}: no law fitted or stored")
        own = flat_round_law(stored)
    shapes = group_aspect_ratios()
    return RollingLaw.by_aspect([(shapes[group], own)] + [(shapes[g], laws[g]) for g in LONG_PATCHES])


def flat_round_law(law: RollingLaw) -> RollingLaw:
    """The single-shape law a table's ``law`` gives a round patch (its first a/b) on a flat surface (convexity 0,
    the blocks'), on the law's own grid."""
    if law.aspect_ratio is None:
        return law
    x, c = np.meshgrid(np.asarray(law.p0_over_p2), np.asarray(law.traction_coefficient))
    params = law.parameters(x, c, law.aspect_ratio[0], 0.0 if law.convexity is not None else None)
    return RollingLaw(law.p0_over_p2, law.traction_coefficient, *(v.tolist() for v in params),
                      source=f"{law.node(0).source} (round patch, flat)")


def long_patch_index(group: str, law: RollingLaw) -> int:
    """The index of the :data:`LONG_PATCHES` group ``group`` among the patch-shape nodes of a table's ``law``: its
    last nodes, one each (the round nodes come first, one per convexity)."""
    return len(law.aspect_ratio) - len(LONG_PATCHES) + LONG_PATCHES.index(group)


def with_nodes(table_rel: str, fitted: dict[str, RollingLaw]) -> RollingLaw:
    """The table's stored law with the nodes of the :data:`LONG_PATCHES` groups {group: law} ``fitted`` replaced,
    the others (and every node's a/b and convexity) kept (KeyError when the table holds no law with patch-shape
    nodes)."""
    stored = LayerTable.read(ROOT / table_rel).rolling_law
    if stored is None or stored.aspect_ratio is None:
        raise KeyError(f"{table_rel}: no law with patch-shape nodes stored")
    by_index = {long_patch_index(g, stored): law for g, law in fitted.items()}
    convexity = stored.convexity or [None] * len(stored.aspect_ratio)
    return RollingLaw.by_shape([(a, s, by_index.get(k, stored.node(k)))
                                for k, (a, s) in enumerate(zip(stored.aspect_ratio, convexity))])


def write_block_nodes(laws: dict[str, RollingLaw]) -> list[Path]:
    """Write the :data:`BLOCK_NODES` laws of ``laws`` into the tables of :data:`GROUPS`, their other nodes kept
    (the round and long-patch nodes come from the sections: :mod:`benchmarks.rolling_section_law`)."""
    fitted = {g: laws[g] for g in BLOCK_NODES}
    return [write_law(table_rel, with_nodes(table_rel, fitted)) for _, table_rel in GROUPS.values() if table_rel]


def shape_check_markdown(results: list, laws: dict) -> list[str]:
    """The shape-check cases: the FEM groove over the block's static dent against the table's law with its
    patch-shape nodes at the case's a/b, and against its round node alone (markdown lines)."""
    md = ["| position | a/b | c | p0 / p_y | FEM groove / static dent, passes 1.. | shaped law / FEM "
          "| round law / FEM |", "|---|---|---|---|---|---|---|"]
    worst = {"shaped": 0.0, "round": 0.0}
    table_laws: dict[str, RollingLaw] = {}  # each table's law built once
    for r in sorted(results, key=lambda r: (r.a_mm / r.b_mm, r.traction, r.p0_over_py)):
        if not r.groove_mm:
            continue
        group = next(g for g, (_, table) in GROUPS.items() if table and table == r.table)
        if group not in table_laws:
            table_laws[group] = shaped_law(group, laws)
        law = table_laws[group]
        n = np.arange(1, len(r.groove_mm) + 1)
        g = np.asarray(r.groove_mm) / r.static_dent_mm
        shaped = law.factor(n, r.p0_over_py, r.traction, r.a_mm / r.b_mm) / g
        round_ = law.factor(n, r.p0_over_py, r.traction, law.aspect_ratio[0]) / g
        worst = {"shaped": max(worst["shaped"], float(np.max(np.abs(shaped - 1)))),
                 "round": max(worst["round"], float(np.max(np.abs(round_ - 1))))}
        md.append(f"| {r.position} | {r.a_mm / r.b_mm:.2f} | {r.traction:g} | {r.p0_over_py:g} | {_joined(g)} | "
                  f"{_joined(shaped)} | {_joined(round_)} |")
    md += ["", f"Worst |law / FEM - 1|: {100 * worst['shaped']:.1f} % with the patch-shape nodes, "
               f"{100 * worst['round']:.1f} % with the round patches' law alone."]
    return md


def own_block_line(rows_own: list[GapRow]) -> str:
    """One sentence: the rolling law on the half-space layer fitted to the a/2 block's own static indentations
    (the rolling run's own layer, like for like) against the a/2 FEM groove, worst over passes and cases."""
    hs = [r for r in rows_own if r.group == "half-space"]
    if not hs:
        return ""
    worst = max(hs, key=lambda r: r.error("rolling_mm"))
    return (f"The half-space's layer fitted instead to the a/2 block's own static indentations (the rolling run's "
            f"own layer, like for like): the rolling law on it within {100 * worst.error('rolling_mm'):.1f} % of the "
            f"a/2 FEM groove at passes 1, 2, 5, 10 in all {len(hs)} cases (worst {worst.key}).")


def _joined(values) -> str:
    return ", ".join(f"{v:.3f}" for v in values)


def write_law(table_rel: str, law: RollingLaw) -> Path:
    """Write ``law`` into the shipped table ``table_rel`` (its CSV is unchanged)."""
    path = ROOT / table_rel
    table = LayerTable.read(path)
    table = replace(table, rolling_law=law)
    return table.write(path)[0]


__all__ = ["BLOCK_NODES", "GROUPS", "GapRow", "HalfspaceStatic", "LAYER_FIT", "MIN_FEM_PASSES", "REPORTED_PASSES",
           "STAND_INS", "TARGET", "fit_group", "gap_rows", "group_of", "layer_static_residuals", "load_results",
           "long_patch_index", "with_nodes", "with_stand_ins", "write_block_nodes", "write_law"]
