"""``python -m benchmarks [--quick|--full] [--only NAME ...] --out DIR``: run every benchmark and write a report.

Each module ``benchmarks/bench_<area>.py`` exposes ``run(mode, out) -> dict`` with ``title``, ``markdown``,
``figures`` (PNG paths) and ``data``. The report ``DIR/report.md`` collects them after the machine facts;
``DIR/report.json`` holds all numbers. A benchmark that raises is reported as failed and the run exits non-zero.
Units: seconds, MiB, mm, N, MPa.
"""

from __future__ import annotations

import argparse
import importlib
import json
import pkgutil
import sys
import time
import traceback
from pathlib import Path

from benchmarks.harness import command_line, machine_info, max_rss_mb, report_stamp
from wrlayer.atomic_write import atomic_write_text
from wrlayer.version import version_text


def discover() -> list[str]:
    """Names of the benchmark modules (``bench_*``), sorted."""
    pkg_dir = Path(__file__).parent
    return sorted(m.name for m in pkgutil.iter_modules([str(pkg_dir)]) if m.name.startswith("bench_"))


def _machine_markdown(info: dict) -> str:
    pk = ", ".join(f"{k} {v}" for k, v in info["packages"].items() if v)
    return (f"- cores: {info['cores']}, CPU: {info['cpu_model']}, memory: {info['memory_GiB']} GiB\n"
            f"- Python {info['python']} on {info['platform']}\n- packages: {pk}\n"
            f"- code version: {info['code_version']}\n")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks", description=__doc__.splitlines()[0])
    ap.add_argument("--version", action="version", version=version_text("python -m benchmarks"))
    mode = ap.add_mutually_exclusive_group()
    mode.add_argument("--quick", action="store_const", dest="mode", const="quick",
                      help="about 2.5 minutes on 2 idle cores (default)")
    mode.add_argument("--full", action="store_const", dest="mode", const="full", help="all levels, longer")
    ap.add_argument("--only", nargs="*", default=None, help="benchmark names, e.g. contact fem")
    ap.add_argument("--out", type=Path, default=Path("out/bench"))
    args = ap.parse_args(argv)
    run_mode = args.mode or "quick"
    names = discover()
    if args.only:
        wanted = {n if n.startswith("bench_") else f"bench_{n}" for n in args.only}
        unknown = wanted - set(names)
        if unknown:
            print(f"error: --only: unknown benchmark(s) {sorted(unknown)}; available: {names}", file=sys.stderr)
            return 2
        names = [n for n in names if n in wanted]
    args.out.mkdir(parents=True, exist_ok=True)
    info = machine_info()
    sections, failed, data = [], [], {"machine": info, "mode": run_mode, "benchmarks": {}}
    for name in names:
        print(f"[bench] {name} ({run_mode}) ...", flush=True)
        t0 = time.perf_counter()
        try:
            mod = importlib.import_module(f"benchmarks.{name}")
            if not callable(getattr(mod, "run", None)):  # its own command line: long runs, or a comparison
                sections.append(f"## {name}\n\nA command-line benchmark, not run here: `python -m benchmarks.{name} "
                                "--help`.\n")
                print(f"[bench] {name}: command line only (python -m benchmarks.{name})", flush=True)
                continue
            res = mod.run(run_mode, args.out)
        except Exception:  # a failing benchmark is reported, the others still run
            failed.append(name)
            tb = traceback.format_exc()
            print(tb, file=sys.stderr)
            sections.append(f"## {name}: FAILED\n\n```\n{tb[-3000:]}\n```\n")
            continue
        wall = time.perf_counter() - t0
        figs = "".join(f"\n![{Path(f).stem}]({Path(f).resolve().relative_to(args.out.resolve())})\n"
                       for f in res.get("figures", []))
        sections.append(f"## {res.get('title', name)}\n\n{res.get('markdown', '')}\n{figs}\n"
                        f"_benchmark wall time {wall:.1f} s_\n")
        data["benchmarks"][name] = {"title": res.get("title"), "wall_s": wall, "data": res.get("data")}
        print(f"[bench] {name} done in {wall:.1f} s", flush=True)
    data["max_rss_MiB"] = max_rss_mb()
    stamp = report_stamp(command_line("python -m benchmarks", argv))
    report = (f"# Benchmark report ({run_mode} mode)\n\n{stamp}\n\nTimings are medians of repeated runs after warm-up; "
              f"comparisons are interleaved and given as ratios.\n\n## Machine\n\n{_machine_markdown(info)}\n"
              + "\n".join(sections)
              + f"\nPeak resident memory of the benchmark process: {data['max_rss_MiB']:.0f} MiB.\n")
    atomic_write_text(args.out / "report.md", report)
    atomic_write_text(args.out / "report.json", json.dumps(data, indent=2, default=float))
    print(f"[bench] report: {args.out / 'report.md'}" + (f"; FAILED: {failed}" if failed else ""))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
