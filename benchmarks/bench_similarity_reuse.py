"""When a section's elastic solve can be reused: how far the ratios p_y / master and c_el / master of a position move
between two profiles, against how far its patch moved (units mm, MPa, s).

``[run] similarity_elastic = "all"`` gives every served position p_y and c_el from an elastic solve of its own
section (:mod:`calibration.similarity.elastic`), but keeps a reference's ratios while the patch stays within
:data:`calibration.similarity.elastic.REUSE_LIMITS` of the reference's. This benchmark measures that rule on the
wear example's profiles: the initial profiles and those after each of its steps (``scenes/wear/s1002_60e1.toml``,
right side, run here), and the worn cases of ``benchmarks/bench_similarity_worn.py`` (after 3000 km and that wear
x5). Every position of the default calibration (its patch from the profile and its mate) is solved on every profile
(cached in ``OUT/cache``), and every pair of profiles is classed by how far the patch moved: not at all (the same
patch on a re-sampled or worn-elsewhere profile: what a new solve scatters by), within the reuse limits, within the
anchor's (:data:`calibration.similarity.anchor.ANCHOR_LIMITS`), beyond. Also: the solves the rule makes at each of
the example's recalibrations (each position's reference the last one solved, the initial profile's direct FEM
first). Regenerate::

    python -m benchmarks.bench_similarity_reuse [--master MASTER_DIR] [--out OUT] [--report FILE]
"""

from __future__ import annotations

import argparse
import math
import tempfile
from pathlib import Path

import numpy as np

from benchmarks.bench_similarity import CONFIG, MASTER, ROOT, WEAR, _config, _master
from benchmarks.bench_similarity_worn import SAME_PATCH, WORN_CASES, WORN_DATA
from benchmarks.harness import publish

OUT = ROOT / "out" / "similarity_reuse"
#: The calibration the positions come from: the worn cases' configuration, its profile files replaced.
TEMPLATE = WORN_DATA / "worn_3000km.toml"
#: The wear example's side whose profiles are taken.
SIDE = "right"


def wear_states(folder: Path) -> list[tuple[str, Path]]:
    """[(name, configuration)] of the wear example's initial profiles and those after each step (its right side),
    written into ``folder``, then the worn cases of the similarity-worn benchmark."""
    import tomllib

    from contact.wear.loop import run_wear
    from contact.wear.recalibrate import write_profiles
    from contact.wear.scene import parse_wear_scene

    data = tomllib.loads(WEAR.read_text())
    for key, value in data.get("layers", {}).items():
        if isinstance(value, str) and value.endswith(".json"):
            data["layers"][key] = str((WEAR.parent / value).resolve())
    run = run_wear(parse_wear_scene(data, WEAR), show_progress=False, work_dir=folder / "wear")
    profiles = [run.initial_profiles[SIDE]] + [rec.profiles[SIDE] for rec in run.steps]
    text = TEMPLATE.read_text()
    states = []
    for k, prof in enumerate(profiles):
        files = write_profiles(prof, folder / f"step_{k}", "wear example")
        cfg = folder / f"step_{k}" / "calibration.toml"
        cfg.write_text(text.replace('"worn_3000km_rail.prr"', f'"{files["rail"]}"')
                       .replace('"worn_3000km_wheel.prw"', f'"{files["wheel"]}"'))
        states.append((f"step {k}", cfg))
    return states + [(name, WORN_DATA / f"{name}.toml") for name in WORN_CASES]


def position_ratios(config: Path, master, cache: Path) -> dict[tuple[str, float], dict]:
    """{(body, y): patch a, b (mm), convexity c (-), p_y / master and c_el / master (-)} of the served positions of
    ``config``, each from its section's elastic solve (on 2 workers, cached in ``cache``)."""
    from calibration.config import load_config
    from calibration.similarity.elastic import section_elastics, with_section
    from calibration.similarity.route import route
    from calibration.tasks import make_tasks

    tasks = make_tasks(load_config(config), Path(tempfile.gettempdir()), False)[0]
    ranges = (master.aspect_range, master.convexity_range)
    served = {t.key: (t, r) for t in tasks if (r := route(t, ranges)).method == "similarity"}
    elastics, failed = section_elastics([t for t, _ in served.values()], cache, 2, "", lambda *a: None)
    if failed:
        raise SystemExit(f"error: {config}: section solves failed: {failed}")
    out = {}
    for key, (t, r) in served.items():
        g, ratios = t.geometry, with_section(None, master, t, r.convexity, elastics[key])
        out[t.body, t.y_mm] = {"a": g.a_mm, "b": g.b_mm, "c": r.convexity, "p_y": ratios.p_y_ratio,
                               "c_el": ratios.compliance_ratio}
    return out


def within(one: dict, other: dict, limits) -> bool:
    """True when the patches of ``one`` and ``other`` lie within ``limits`` (a PatchLimits) of each other
    (:func:`calibration.similarity.anchor.patch_moved`)."""
    from types import SimpleNamespace

    from calibration.similarity.anchor import patch_moved

    ref = SimpleNamespace(a_mm=other["a"], b_mm=other["b"], convexity=other["c"],
                          length_mm=math.sqrt(other["a"] * other["b"]))
    return not patch_moved(ref, one["a"], one["b"], one["c"], limits)


def pair_classes(ratios: dict[str, dict]) -> dict[str, list[tuple[float, float]]]:
    """{class: [(|change of p_y ratio|, |change of c_el ratio|) in %]} over every pair of profiles and every
    position served on both: "same patch" (within 1e-4 in c, 1e-3 in log a/b and log size), "within the reuse
    limits", "within the anchor's limits" (beyond the reuse limits), "beyond"."""
    from calibration.similarity.anchor import ANCHOR_LIMITS
    from calibration.similarity.elastic import REUSE_LIMITS

    classes: dict[str, list[tuple[float, float]]] = {"same patch": [], "within the reuse limits": [],
                                                     "within the anchor's limits": [], "beyond": []}
    names = list(ratios)
    for i, one in enumerate(names):
        for other in names[i + 1:]:
            for key, r1 in ratios[one].items():
                r2 = ratios[other].get(key)
                if r2 is None:
                    continue
                change = (100 * abs(r2["p_y"] / r1["p_y"] - 1), 100 * abs(r2["c_el"] / r1["c_el"] - 1))
                kind = next(k for k, lim in (("same patch", SAME_PATCH), ("within the reuse limits", REUSE_LIMITS),
                                             ("within the anchor's limits", ANCHOR_LIMITS), ("beyond", None))
                            if lim is None or within(r1, r2, lim))
                classes[kind].append(change)
    return classes


def solves_along(ratios: dict[str, dict], steps: list[str]) -> list[int]:
    """The solves of ``similarity_elastic = "all"`` at the recalibration after each of ``steps[1:]`` (the wear
    example recalibrates after each step but the last; ``steps[0]``: the initial profile, whose patches stand for
    the first references. The loop itself compares with its scene tables' patches, calibrated on the builtin
    profiles, which differ at a few positions from those on the written initial profile files: it may solve more)."""
    from calibration.similarity.elastic import REUSE_LIMITS

    reference = dict(ratios[steps[0]])
    counts = []
    for name in steps[1:]:
        moved = [key for key, r in ratios[name].items() if key not in reference
                 or not within(r, reference[key], REUSE_LIMITS)]
        reference.update({key: ratios[name][key] for key in moved})
        counts.append(len(moved))
    return counts


def measure(master_dir: Path = MASTER, out: Path = OUT) -> dict:
    master, why = _master(_config(CONFIG, master_dir), quick=True)
    if master is None:
        raise SystemExit(f"error: {master_dir}: {why}")
    out.mkdir(parents=True, exist_ok=True)
    states = wear_states(out)
    ratios = {name: position_ratios(cfg, master, out / "cache") for name, cfg in states}
    classes = pair_classes(ratios)
    steps = [name for name, _ in states if name.startswith("step ")]
    stats = {k: {"pairs": len(v), **{q: [float(np.percentile([c[i] for c in v], p)) if v else math.nan
                                          for p in (50, 90, 100)] for i, q in enumerate(("p_y", "c_el"))}}
             for k, v in classes.items()}
    return {"states": [n for n, _ in states], "classes": stats, "solves": solves_along(ratios, steps[:-1]),
            "positions": len(ratios[steps[0]])}


def markdown(data: dict) -> str:
    from calibration.similarity.anchor import ANCHOR_LIMITS
    from calibration.similarity.elastic import REUSE_LIMITS

    lim = {"within the reuse limits": REUSE_LIMITS, "within the anchor's limits": ANCHOR_LIMITS}
    md = ["| patch moved | pairs | p_y / master: median, 90 %, largest change [%] | c_el / master: median, 90 %, "
          "largest [%] |", "|---|---|---|---|"]
    for kind, s in data["classes"].items():
        note = f" (b/(2R) {lim[kind].convexity:g}, a/b x{lim[kind].aspect_factor:g}, sqrt(ab) " \
               f"x{lim[kind].size_factor:g})" if kind in lim else ""
        md.append(f"| {kind}{note} | {s['pairs']} | {' / '.join(f'{v:.3f}' for v in s['p_y'])} | "
                  f"{' / '.join(f'{v:.3f}' for v in s['c_el'])} |")
    md += ["", f"Profiles: {', '.join(data['states'])} ({data['positions']} served positions each; every pair). "
               "'same patch': within 1e-4 in b/(2R) and 0.1 % in a/b and sqrt(ab), the scatter of a new solve "
               "(its mesh follows the profile's points). The reuse limits' classes exclude the closer ones.",
           f"Solves of `similarity_elastic = \"all\"` at the wear example's recalibrations (after steps "
           f"1..{len(data['solves'])}, right side): {', '.join(str(n) for n in data['solves'])} of "
           f"{data['positions']} positions."]
    return "\n".join(md)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.bench_similarity_reuse",
                                 description=__doc__.splitlines()[0])
    ap.add_argument("--master", type=Path, default=MASTER, help="the master's FEM cache folder")
    ap.add_argument("--out", type=Path, default=OUT, help="profiles and the solves' cache")
    ap.add_argument("--report", type=Path, default=None, help="write the report (markdown, stamped) here")
    args = ap.parse_args(argv)
    publish(args.report, "Similarity: reusing a section's elastic solve", markdown(measure(args.master, args.out)),
            "python -m benchmarks.bench_similarity_reuse", argv)


if __name__ == "__main__":
    main()
