"""Similarity on worn profiles: the master alone and the master anchored to the new profile's direct FEM, against
the direct 3D FEM of the worn profile (units mm, MPa, s).

For every worn case (a calibration configuration of the worn profiles and its direct run's output folder) and every
position the master serves: the errors of :func:`calibration.similarity.route.similar_indentation` ("master") and
of the same anchored to the reference run's direct table at the same y (:mod:`calibration.similarity.anchor`,
"anchored everywhere"), and the wear loop's rule: anchored where the patch is like the reference's, else the
master's (``reanchor = false``, the default) or the direct FEM (``reanchor = true``: then exact, at the cost of one
FEM position each), each against the worn profile's direct FEM at equal p0 (MPa), counted as
:mod:`benchmarks.bench_similarity` counts them (p_y, u_pl at every level, residual at every peak; target 2 %). The
reference is the configuration the shipped tables come from and its direct run's tables.

    python -m benchmarks.bench_similarity_worn --reference-config calibration/configs/default.toml
        --reference DIRECT_OUT --master MASTER_DIR --worn WORN.toml:WORN_DIRECT_OUT [...] [--sections]
        [--report FILE]

(``--sections``: also the loop's rule with p_y and c_el from each position's own section,
:mod:`calibration.similarity.elastic`.)

Each ``WORN_DIRECT_OUT`` is ``wrlayer calibrate WORN.toml --out WORN_DIRECT_OUT`` with ``run.method = "direct"``;
the worn cases of the report are ``benchmarks/data/similarity_worn/worn_3000km.toml`` (the wear example's profiles
after 3000 km) and ``worn_x5.toml`` (that wear x5), about 5 min of FEM each on 2 cores.
"""

from __future__ import annotations

import argparse
import math
import tempfile
from pathlib import Path


from benchmarks.bench_similarity import (CONFIG, DIRECT_OUT, MASTER, ROOT, TARGET, _config, _direct, _master, _pct,
                                         compare)
from benchmarks.harness import publish
from calibration.similarity.anchor import PatchLimits

#: Within these limits a worn patch is the reference's own (the direct FEM's scatter under a re-sampled profile).
SAME_PATCH = PatchLimits(convexity=1e-4, aspect_factor=math.exp(1e-3), size_factor=math.exp(1e-3))

#: The worn cases of the report: configurations in benchmarks/data/similarity_worn, direct runs in out/similarity_worn.
WORN_CASES = ("worn_3000km", "worn_x5")
WORN_DATA = ROOT / "benchmarks" / "data" / "similarity_worn"
WORN_OUT = ROOT / "out" / "similarity_worn"


def references(ref_config: Path, ref_out: Path) -> dict:
    """{(body, y): DirectReference} of the reference run's direct tables (``REF_OUT/<body>_layer_table.json``),
    each with its profile's convexity over the patch."""
    from calibration.config import load_config, profile_of
    from calibration.similarity.anchor import table_references
    from wrlayer.layer_table import LayerTable

    cfg = load_config(ref_config)
    out = {}
    for b in cfg.bodies:
        table = LayerTable.read(Path(ref_out) / f"{b.body}_layer_table.json")
        out.update(table_references(table, profile_of(b.profile)))
    return out


def worn_case(worn_config: Path, worn_out: Path, master, refs: dict, sections: bool = False) -> list[dict]:
    """One row per position of ``worn_config``: the master's errors, the errors anchored everywhere and those of
    the wear loop's rule (anchored where :func:`calibration.similarity.anchor.applies`, else the master's); with
    ``sections`` also the loop's rule with p_y and c_el from each position's own section
    (:mod:`calibration.similarity.elastic`, solved on 2 workers and cached in ``worn_out/cache``)."""
    from calibration.similarity.anchor import anchor, anchored, applies, patch_moved
    from calibration.similarity.elastic import needs_solve, section_elastics, with_section
    from calibration.similarity.route import route, task_indentation
    from calibration.tasks import make_tasks

    cfg = _config(worn_config, Path(tempfile.gettempdir()))
    direct, missing = _direct(cfg, worn_out, quick=True)
    if missing:
        raise SystemExit(f"error: {worn_out}: {missing}")
    tasks, _, _ = make_tasks(cfg, Path(tempfile.gettempdir()), False)
    ranges = (master.aspect_range, master.convexity_range)
    elastics = section_elastics(tasks, Path(worn_out) / "cache", 2, "", lambda *a: None)[0] if sections else {}
    rows = []
    for t in tasks:
        r = route(t, ranges)
        served = r.method == "similarity"
        if not served:  # the wear loop's recalibration serves it from the master's nearest point
            r = route(t, ranges, "nearest")
        g = t.geometry
        sim = task_indentation(master, t, r.convexity, r.plastic_convexity)
        row = {"body": t.body, "y_mm": t.y_mm, "served": served, "convexity": r.convexity, "a_over_b": g.a_mm / g.b_mm,
               "length_mm": math.sqrt(g.a_mm * g.b_mm), "master": compare(direct[t.body, t.y_mm], sim, cfg.load)}
        ref = refs.get((t.body, t.y_mm))
        row["loop"] = row["master"]
        if ref is not None:
            row["anchored"] = compare(direct[t.body, t.y_mm], anchored(sim, anchor(master, ref), row["length_mm"]),
                                      cfg.load)
            row["reference"] = {"convexity": ref.convexity, "a_over_b": ref.a_mm / ref.b_mm,
                                "length_mm": ref.length_mm}
            row["anchor_applies"] = not applies(ref, g.a_mm, g.b_mm, r.convexity)
            if not patch_moved(ref, g.a_mm, g.b_mm, r.convexity, SAME_PATCH):  # the reference's own scatter
                row["same_patch_direct"] = compare(direct[t.body, t.y_mm], _as_result(ref), cfg.load)
            row["loop"] = row["anchored"] if row["anchor_applies"] else row["master"]
        if t.key in elastics:  # the loop's rule with the section's p_y and c_el
            correction = anchor(master, ref) if row.get("anchor_applies") else None
            fixed = anchored(sim, with_section(correction, master, t, r.convexity, elastics[t.key]), row["length_mm"])
            row["loop_section_everywhere"] = compare(direct[t.body, t.y_mm], fixed, cfg.load)
            # similarity_elastic = "all": the reference's ratios where the patch stayed within the reuse limits
            row["section_reused"] = not needs_solve(ref, t, r.convexity)
            row["loop_section"] = row["anchored"] if row["section_reused"] else row["loop_section_everywhere"]
            # similarity_elastic = "unanchored": the section's solve only where no anchor applies
            row["loop_unanchored"] = row["loop"] if row.get("anchor_applies") else row["loop_section"]
        rows.append(row)
    return rows


def _as_result(ref):
    """A :class:`calibration.similarity.anchor.DirectReference`'s curves in the attribute names :func:`compare`
    reads from a result."""
    from types import SimpleNamespace

    return SimpleNamespace(first_yield_MPa=ref.p_y_MPa, p_MPa=ref.p_MPa, u_pl_mm=ref.u_pl_mm,
                           unload_peaks_MPa=ref.peaks_MPa, residual_fem_mm=ref.residual_mm)


def _worst(err: dict) -> float:
    return max(abs(err["p_y"]), err["u_pl"], err["residual"])


KINDS = ("master", "anchored", "loop", "loop_section", "loop_unanchored", "loop_section_everywhere")


def run_cases(ref_config: Path, ref_out: Path, master_dir: Path, worn: list[tuple[Path, Path]],
              sections: bool = False) -> dict:
    """The rows of every worn case and, over the served positions, the counts within the target and the worst
    error of each kind (master, anchored everywhere, the loop's rule, with ``sections`` that rule with each
    section's elastic solve)."""
    cfg = _config(ref_config, master_dir)
    master, why = _master(cfg, quick=True)
    if master is None:
        raise SystemExit(f"error: {master_dir}: {why}")
    refs = references(ref_config, ref_out)
    cases = []
    for config, out in worn:
        rows = worn_case(config, out, master, refs, sections)
        served = [r for r in rows if r["served"]]
        within = {k: sum(1 for r in served if k in r and _worst(r[k]) <= TARGET) for k in KINDS}
        worst = {k: max((_worst(r[k]) for r in served if k in r), default=math.nan) for k in KINDS}
        same = [r["same_patch_direct"] for r in served if "same_patch_direct" in r]
        cases.append({"config": str(config), "rows": rows, "served": len(served), "within": within, "worst": worst,
                      "anchors_applied": sum(1 for r in served if r.get("anchor_applies")),
                      "same_patch": {"positions": len(same), "worst": max(map(_worst, same), default=math.nan),
                                     "p_y": max((abs(e["p_y"]) for e in same), default=math.nan)}})
    return {"cases": cases, "target": TARGET, "reference": str(ref_out)}


def _errors(err: dict | None) -> str:
    return f"{_pct(err['p_y'])}, {100 * err['u_pl']:.2f}, {100 * err['residual']:.2f}" if err else "no reference"


def markdown(data: dict) -> str:
    md = []
    for case in data["cases"]:
        md += [f"### {Path(case['config']).name}", "",
               "| body | y [mm] | route | a/b, sqrt(ab) [mm], b/(2R): worn / new | master: p_y, u_pl, residual [%] | "
               "anchored everywhere [%] | anchor applies |", "|---|---|---|---|---|---|---|"]
        for r in case["rows"]:
            ref = r.get("reference")
            shape = (f"{r['a_over_b']:.2f}, {r['length_mm']:.2f}, {r['convexity']:+.3f} / "
                     + (f"{ref['a_over_b']:.2f}, {ref['length_mm']:.2f}, {ref['convexity']:+.3f}" if ref else "-"))
            md.append(f"| {r['body']} | {r['y_mm']:g} | {'served' if r['served'] else 'nearest point'} | {shape} | "
                      f"{_errors(r['master'])} | {_errors(r.get('anchored'))} | "
                      f"{'yes' if r.get('anchor_applies') else 'no'} |")
        n, w, k = case["served"], case["worst"], case["within"]
        md += ["", f"Served {n} of {len(case['rows'])} positions (the others reach past the profile's end: the wear "
                   f"loop serves them from the master's nearest point; not counted). Within {100 * data['target']:g} % "
                   f"on p_y, u_pl at every level and every residual: master {k['master']}, anchored everywhere "
                   f"{k['anchored']}, the loop's rule (anchored at the {case['anchors_applied']} positions where the "
                   f"anchor applies) {k['loop']} with `reanchor = false` (the default); worst: {100 * w['master']:.2f} %, "
                   f"{100 * w['anchored']:.2f} %, {100 * w['loop']:.2f} %. With `reanchor = true` the "
                   f"{n - case['anchors_applied']} others are computed by the direct FEM: "
                   f"{k['loop'] + sum(1 for r in case['rows'] if r['served'] and not r.get('anchor_applies') and _worst(r['loop']) > data['target'])} "
                   f"of {n} within {100 * data['target']:g} %, for {n - case['anchors_applied']} FEM positions."]
        if any("loop_section" in r for r in case["rows"]):
            md.append(_sections_line(case, data["target"]))
        same = case.get("same_patch", {})
        if same.get("positions"):
            md.append(f"The direct FEM against itself: at the {same['positions']} served positions whose worn patch "
                      "is the new one's (b/(2R) within 1e-4, a/b and sqrt(ab) within 0.1 %; the profile re-sampled or "
                      "worn elsewhere, so the mesh moved), the new profile's direct FEM is within "
                      f"{100 * same['worst']:.2f} % of the worn one's (p_y within {100 * same['p_y']:.2f} %): how far "
                      "the reference itself scatters under the 2 % target.")
        md.append("")
    md.append("Errors at equal p0 (MPa) against the worn profile's direct FEM, relative as in the similarity report "
              f"(p_y signed; u_pl and residual: worst over the levels); anchored to the direct tables in "
              f"{data['reference']}.")
    return "\n".join(md)


def _sections_line(case: dict, target: float) -> str:
    """The loop's rule with each section's elastic solve (``similarity_elastic = "all"``) and with it only where no
    anchor applies (``"unanchored"``): count, worst, misses."""
    served = [r for r in case["rows"] if r["served"] and "loop_section" in r]
    text = []
    for kind, what in (("loop_section", f'`similarity_elastic = "all"`: an elastic solve at the '
                                        f'{sum(1 for r in served if not r.get("section_reused"))} positions whose '
                                        "patch left its reference's by more than the reuse limits, the reference's "
                                        "ratios elsewhere"),
                       ("loop_unanchored", f'`similarity_elastic = "unanchored"`: an elastic solve at the '
                                           f'{sum(1 for r in served if not r.get("anchor_applies"))} positions '
                                           "where no anchor applies, the anchor's p_y and c_el elsewhere"),
                       ("loop_section_everywhere", f"an elastic solve at every one of the {len(served)} positions")):
        misses = [f"{r['body']} {r['y_mm']:g} ({100 * _worst(r[kind]):.1f} %)" for r in served
                  if _worst(r[kind]) > target]
        text.append(f"The loop's rule with p_y and c_el from the position's own section ({what}): "
                    f"{case['within'][kind]} of {len(served)} within {100 * target:g} %, worst "
                    f"{100 * case['worst'][kind]:.2f} %" + (f"; misses: {', '.join(misses)}." if misses else "."))
    return "\n\n".join(text)


def run(mode: str, out: Path) -> dict:
    """``python -m benchmarks``: the report's cases from the default folders (the reference's direct run in
    ``out/calibration_direct``, the master in ``out/calibration/cache``, the worn runs in ``out/similarity_worn``);
    the full mode computes what is missing (about 5 min of FEM per worn case on 2 cores, more for the reference and
    the master), the quick mode says what is missing."""
    worn = [(WORN_DATA / f"{name}.toml", WORN_OUT / name) for name in WORN_CASES]
    quick = mode != "full"
    missing = [why for why in (_master(_config(CONFIG, MASTER), quick)[1],
                               _direct(_config(CONFIG, MASTER), DIRECT_OUT, quick)[1]) if why]
    missing += [why for config, folder in worn if (why := _direct(_config(config, MASTER), folder, quick)[1])]
    title = "Similarity on worn profiles"
    if missing:
        return {"title": title, "markdown": f"Not measured: {'; '.join(missing)} (run the full mode).",
                "figures": [], "data": {"missing": missing}}
    data = run_cases(CONFIG, DIRECT_OUT, MASTER, worn)
    return {"title": title, "markdown": markdown(data), "figures": [], "data": data}


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.bench_similarity_worn", description=__doc__.splitlines()[0])
    ap.add_argument("--reference-config", type=Path, default=CONFIG)
    ap.add_argument("--reference", type=Path, required=True, help="the reference configuration's direct run folder")
    ap.add_argument("--master", type=Path, default=MASTER, help="the master's FEM cache folder")
    ap.add_argument("--worn", action="append", required=True, metavar="CONFIG:DIRECT_OUT",
                    help="a worn profiles' configuration and its direct run folder (repeatable)")
    ap.add_argument("--sections", action="store_true",
                    help="also the loop's rule with p_y and c_el from each position's own section's elastic solve")
    ap.add_argument("--report", type=Path, default=None, help="write the report (markdown, stamped) here")
    args = ap.parse_args(argv)
    worn = []
    for item in args.worn:
        config, sep, out = item.partition(":")
        if not sep:
            ap.error(f"--worn {item}: expected CONFIG:DIRECT_OUT")
        worn.append((Path(config), Path(out)))
    data = run_cases(args.reference_config, args.reference, args.master, worn, args.sections)
    publish(args.report, "Similarity on worn profiles", markdown(data), "python -m benchmarks.bench_similarity_worn",
            argv)


if __name__ == "__main__":
    main()
