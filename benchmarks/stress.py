"""Numerical stress tests: ``python -m benchmarks.stress [--quick|--full] --out DIR [--seed S] [--cases N]``.

Contact solver (:mod:`benchmarks.stress_contact`): seeded random scenes, 100 (quick) or 5000 (full) cases.
FEM engine (:mod:`benchmarks.stress_fem`): far too large load increments, nearly perfectly plastic material, the
limit load, very coarse and (full only) very fine meshes, Poisson's ratio 0.499.

Every case must end in an accepted outcome (a result that passes the invariants / verification, or the project's
clear error type where one is acceptable). Anything else (a violated invariant, another exception type, a failed
recovery) is a failure: it is listed with the seed or case name that reproduces it, and the run exits with 1.
Writes ``DIR/stress.md`` and ``DIR/stress.json`` (atomically). Units: mm, N, MPa, s.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import traceback
from collections import Counter
from pathlib import Path

from benchmarks.harness import command_line, machine_info, report_stamp
from benchmarks.stress_contact import (
    InvariantViolation,
    check_contact_case,
    random_contact_case,
)
from benchmarks.stress_fem import CENTRE_RTOL, FEM_CASES, run_fem_case
from wrlayer.atomic_write import atomic_write_text
from wrlayer.errors import cli_guard
from wrlayer.version import version_text

CONTACT_ACCEPTED = ("ok", "clear-error")
FEM_ACCEPTED = ("ok", "clear-error")


def run_contact(seeds, progress: bool = False) -> dict:
    """Run the contact cases of ``seeds``; counts per outcome and per separation kind, failures with their seed."""
    counts: Counter = Counter()
    by_kind: dict[str, Counter] = {}
    failures, errors = [], []
    stats = Counter()
    t0 = time.perf_counter()
    slowest = (0.0, None)
    for seed in seeds:
        case = random_contact_case(seed)
        t = time.perf_counter()
        try:
            outcome = check_contact_case(case)
        except InvariantViolation as err:
            outcome = "invariant-violated"
            failures.append({"seed": seed, "case": case.describe(), "problem": str(err)})
        except Exception as err:  # noqa: BLE001 - any other exception is exactly what this run hunts for
            outcome = "unexpected-exception"
            failures.append({"seed": seed, "case": case.describe(), "problem": f"{type(err).__name__}: {err}",
                             "traceback": traceback.format_exc(limit=6)})
        dt = time.perf_counter() - t
        slowest = max(slowest, (dt, seed), key=lambda x: x[0])
        counts[outcome] += 1
        by_kind.setdefault(case.kind, Counter())[outcome] += 1
        if outcome == "clear-error":
            errors.append({"seed": seed, "error": case.stats.get("error", "")})
        if outcome == "ok":
            stats["multi_patch"] += case.stats["patches"] > 1
            stats["full_sliding"] += case.stats["full_sliding"]
            stats["shakedown"] += case.stats["shakedown"]
            stats["shakedown_above_previous_peak"] += case.stats["shakedown_above_previous_peak"]
            stats["passes_total"] += case.stats["passes_run"]
        if progress:
            print(f"\rcontact {sum(counts.values())}/{len(seeds)} {dict(counts)}", end="", file=sys.stderr)
    if progress:
        print(file=sys.stderr)
    return {"cases": len(seeds), "outcomes": dict(counts), "by_kind": {k: dict(v) for k, v in by_kind.items()},
            "stats": dict(stats), "wall_s": time.perf_counter() - t0, "slowest_case_s": slowest[0],
            "slowest_seed": slowest[1], "failures": failures, "clear_errors": errors}


def run_fem(mode: str, progress: bool = False) -> dict:
    """Run the FEM cases of the mode (full: all; quick: those marked quick)."""
    results, failures = [], []
    t0 = time.perf_counter()
    for case in FEM_CASES:
        if mode == "quick" and not case.quick:
            continue
        try:
            r = run_fem_case(case)
        except Exception as err:  # noqa: BLE001
            r = {"case": case.name, "what": case.what, "outcome": "unexpected-exception",
                 "error": f"{type(err).__name__}: {err}", "traceback": traceback.format_exc(limit=6)}
        results.append(r)
        if r["outcome"] not in FEM_ACCEPTED:
            failures.append({"case": r["case"], "problem": r["outcome"] + ": " + str(r.get("error", r))})
        if progress:
            print(f"fem {case.name}: {r['outcome']}", file=sys.stderr)
    return {"cases": results, "outcomes": dict(Counter(r["outcome"] for r in results)), "failures": failures,
            "wall_s": time.perf_counter() - t0}


def _fmt(v, spec: str) -> str:
    return "" if v is None else format(v, spec)


def report_markdown(mode: str, seed0: int, contact: dict, fem: dict, machine: dict, command: str) -> str:
    """The stress report (markdown), stamped with the revision and ``command`` (:func:`report_stamp`)."""
    c = contact
    lines = [f"# Stress tests ({mode})", "", report_stamp(command), "",
             (f"Machine: {machine.get('cpu_model', '?')}, {machine.get('cores', '?')} cores; "
             f"code {machine.get('code_version', '?')}. Timings are wall clock on a shared machine."), "",
             "## Contact solver (random scenes)", "",
             (f"{c['cases']} cases, seeds {seed0}..{seed0 + c['cases'] - 1} "
             "(`benchmarks.stress_contact.random_contact_case(seed)`), "
             f"{c['wall_s']:.1f} s in total, slowest case {c['slowest_case_s']:.1f} s (seed {c['slowest_seed']})."),
             ("Accepted outcomes: `ok` (every invariant holds) and `clear-error` (a `WrLayerError`); "
             "everything else fails the run."), "",
             "| separation | " + " | ".join(sorted(c["outcomes"])) + " |",
             "|---|" + "---|" * len(c["outcomes"])]
    for kind, counts in sorted(c["by_kind"].items()):
        lines.append(f"| {kind} | " + " | ".join(str(counts.get(o, 0)) for o in sorted(c["outcomes"])) + " |")
    lines.append("| **all** | " + " | ".join(f"**{c['outcomes'][o]}**" for o in sorted(c["outcomes"])) + " |")
    s = c["stats"]
    if s:
        lines += ["", (f"Among the `ok` cases: {s.get('multi_patch', 0)} with two patches, {s.get('full_sliding', 0)} "
                  f"in full sliding (every FASTSIM cell slips), {s.get('passes_total', 0)} passes in total, "
                  f"{s.get('shakedown', 0)} ending in shakedown, of which "
                  f"{s.get('shakedown_above_previous_peak', 0)} with hardening and a peak above max(p_2, earlier "
                  "peaks) (alternating plasticity: the Masing residual no longer grows, see "
                  "`benchmarks/stress_contact.py`).")]
    if c["clear_errors"]:
        lines += ["", "Clear errors (first 20):", ""] + [f"- seed {e['seed']}: {e['error']}"
                                                        for e in c["clear_errors"][:20]]
    lines += ["", "## FEM engine", "",
              (f"{len(fem['cases'])} cases in {fem['wall_s']:.1f} s. Verified = equilibrium recomputed from the "
              "returned stresses (relative to |f_ext|, limit 1e-6), applied force vs pi/2 b p0 / 2 (limit 1 %), "
              f"load-centre displacement vs the same problem in p_fy/8 increments with full Newton (limit "
              f"{CENTRE_RTOL:.0%})."), "",
              ("| case | outcome | dofs | p_fy MPa | p0 MPa | increments (auto) | Newton its | equilibrium | "
              "force error | u_centre mm | vs small steps | wall s |"),
              "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in fem["cases"]:
        inc = "" if "increments" not in r else f"{r['increments']} ({r['automatic_substeps']})"
        lines.append(f"| {r['case']} | {r['outcome']} | {r.get('n_dofs', '')} | {_fmt(r.get('p_fy_MPa'), '.1f')} | "
                     f"{_fmt(r.get('p0_MPa'), '.1f')} | {inc} | {r.get('newton_iterations', '')} | "
                     f"{_fmt(r.get('equilibrium_rel'), '.1e')} | {_fmt(r.get('force_rel_error'), '.1e')} | "
                     f"{_fmt(r.get('u_centre_mm'), '.5f')} | {_fmt(r.get('centre_rel_diff'), '.2%')} | "
                     f"{_fmt(r.get('wall_s'), '.1f')} |")
    lines += ["", "Cases:", ""] + [f"- `{r['case']}`: {r['what']}" for r in fem["cases"]]
    errs = [r for r in fem["cases"] if "error" in r]
    if errs:
        lines += ["", "Errors:", ""] + [f"- `{r['case']}` ({r['outcome']}): {r['error'][:400]}" for r in errs]
    failures = c["failures"] + fem["failures"]
    lines += ["", "## Failures", ""]
    if not failures:
        lines.append("None: every case ended in an accepted outcome.")
    for f in c["failures"]:
        lines.append(f"- contact seed {f['seed']} — {f['problem']}  \n  {f['case']}")
    for f in fem["failures"]:
        lines.append(f"- FEM case `{f['case']}` — {f['problem'][:400]}")
    lines += ["", ("Reproduce a contact seed: `python -c \"from benchmarks.stress_contact import *; "
              "print(check_contact_case(random_contact_case(SEED)))\"`.")]
    return "\n".join(lines) + "\n"


@cli_guard
def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.stress", description=__doc__.splitlines()[0])
    ap.add_argument("--version", action="version", version=version_text("python -m benchmarks.stress"))
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--quick", action="store_const", dest="mode", const="quick", help="100 contact cases (default)")
    g.add_argument("--full", action="store_const", dest="mode", const="full", help="5000 contact cases, all FEM")
    ap.add_argument("--out", type=Path, default=Path("out/stress"), help="output directory")
    ap.add_argument("--seed", type=int, default=0, help="first contact seed")
    ap.add_argument("--cases", type=int, default=None, help="number of contact cases (overrides the mode)")
    ap.add_argument("--no-fem", action="store_true", help="skip the FEM cases")
    args = ap.parse_args(argv)
    mode = args.mode or "quick"
    n = args.cases if args.cases is not None else (5000 if mode == "full" else 100)
    progress = sys.stderr.isatty()
    contact = run_contact(range(args.seed, args.seed + n), progress)
    fem = {"cases": [], "outcomes": {}, "failures": [], "wall_s": 0.0} if args.no_fem else run_fem(mode, progress)
    machine = machine_info()
    md = report_markdown(mode, args.seed, contact, fem, machine, command_line("python -m benchmarks.stress", argv))
    data = {"mode": mode, "seed": args.seed, "contact": contact, "fem": fem, "machine": machine}
    atomic_write_text(args.out / "stress.json", json.dumps(data, indent=2, default=str) + "\n")
    atomic_write_text(args.out / "stress.md", md)
    n_fail = len(contact["failures"]) + len(fem["failures"])
    print(f"contact: {contact['outcomes']}; FEM: {fem['outcomes']}; report {args.out / 'stress.md'}")
    if n_fail:
        print(f"{n_fail} failing case(s), see {args.out / 'stress.md'}", file=sys.stderr)
    return 1 if n_fail else 0


if __name__ == "__main__":
    sys.exit(main())
