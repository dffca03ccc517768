"""Command line: ``wrlayer calibrate CONFIG --out DIR [--scheduler ADDRESS] [--workers N]
[--plots/--no-plots] [--quiet]`` and ``wrlayer rolling CONFIG --out DIR [--force] [--quiet]`` (the
moving-load FEM of :mod:`calibration.rolling`, docs/rolling.md; exit 3 when a step fails, the completed passes
written).

Exit codes: 0 all positions calibrated; 2 bad input (configuration, or a run whose estimated cost exceeds the
limit without ``--force``, or ``--out`` in use by another run; nothing written); 3 numerical failure of the
whole run; 4 some positions failed
(their errors on stderr and in summary.json; the tables hold the other positions and list the failed ones, which
the reader does not interpolate across; the computed positions are cached).
"""

from __future__ import annotations

import argparse
import dataclasses
import sys

from wrlayer import cli
from wrlayer.errors import cli_guard


def _parser() -> argparse.ArgumentParser:
    ap = cli.parser("python -m calibration", "FEM calibration of Prandtl surface-layer tables along profiles "
                    "(units mm, N, MPa, s)",
                    ["wrlayer calibrate calibration/configs/default.toml --out out/calibration"])
    sub = ap.add_subparsers(dest="command", required=True)
    run = cli.subparser(sub, "run", "calibrate the bodies and positions of a TOML configuration",
                        ["wrlayer calibrate calibration/configs/test_coarse.toml --out out/cal --no-plots",
                         "wrlayer calibrate my.toml --out out/cal --scheduler tcp://host:8786"])
    run.add_argument("config", help="TOML configuration file")
    cli.add_run_options(run, "output folder (tables, cache, plots, fields)")
    run.add_argument("--scheduler", default=None, help="Dask scheduler address (default: local processes)")
    run.add_argument("--workers", type=int, default=None, help="local worker processes (default: config)")
    run.add_argument("--plots", action=argparse.BooleanOptionalAction, default=None,
                     help="write PNG/VTK pictures (default: config run.plots)")
    cli.add_profile_check_option(run)
    roll = cli.subparser(sub, "rolling", "moving Hertz load pass after pass on an elastic-plastic half-space",
                         ["wrlayer rolling calibration/configs/rolling_halfspace.toml --out out/rolling"])
    roll.add_argument("config", help="TOML rolling configuration file")
    cli.add_run_options(roll, "output folder (rolling.json, fields/)")
    cli.add_profile_check_option(roll)
    return ap


def _rolling(args) -> int:
    from calibration.rolling.config import load_rolling_config  # the FEM stack only once the arguments are valid
    from calibration.rolling.run import run_rolling

    cfg = load_rolling_config(args.config, args.accept_unusual_profile)
    run_rolling(cfg, args.out, force=args.force, progress=None if args.quiet else print)
    return 0


@cli_guard
def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    if args.command == "rolling":
        return _rolling(args)
    from calibration.config import load_config  # the FEM stack only once the arguments are valid
    from calibration.pipeline import calibrate
    from wrlayer.runner import check_workers

    cfg = load_config(args.config, args.accept_unusual_profile)
    if args.workers is not None:
        cfg = dataclasses.replace(cfg, run=dataclasses.replace(cfg.run, workers=check_workers(args.workers,
                                                                                            "--workers")))
    result = calibrate(cfg, args.out, scheduler=args.scheduler, plots=args.plots, show_progress=not args.quiet,
                       force=args.force)
    return 0 if result.ok else 4


if __name__ == "__main__":
    sys.exit(main())
