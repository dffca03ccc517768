"""Command-line conventions shared by every entry point, and the ``wrlayer`` console command.

    wrlayer simulate SCENE --out DIR [--plots]        = python -m contact simulate ...
    wrlayer simulate-all SCENES_DIR --out DIR          = python -m contact simulate-all ...
    wrlayer calibrate CONFIG --out DIR                 = python -m calibration run ...
    wrlayer rolling CONFIG --out DIR                   = python -m calibration rolling ...
    wrlayer mesh PROFILE --y0 Y --h-min H --h-max H --out FILE   = python -m meshes mesh ...
    wrlayer mesh-plots --out DIR                       = python -m meshes plots ...
    wrlayer --version

Every entry point prints ``error: <input>: <what is wrong>`` (one line, no traceback) for bad input and exits
with the codes of :data:`EXIT_CODES`.
"""

from __future__ import annotations

import argparse
import importlib
import sys
from collections.abc import Sequence

from wrlayer.errors import ArgumentParser
from wrlayer.version import version_text

#: Exit codes of every entry point.
EXIT_CODES = {
    0: "success",
    1: "some scenes of a batch (simulate-all) failed; the others were written",
    2: "bad input (file, key, value or argument; a run refused by its cost estimate without --force; an --out in "
       "use by another run or not writable): nothing written",
    3: "numerical failure (an iteration did not converge; out of memory): nothing written",
    4: "some positions of a calibration or cases of a wheel-rail sweep failed (printed on stderr; the tables "
       "and results hold the others and list the failed ones)",
    5: "wear: the loop stopped at a step (named); the completed steps' profiles and table were written",
    130: "interrupted (Ctrl-C)",
    143: "terminated (SIGTERM); the run's staging folders are removed and its workers ended (a wear run keeps its "
         "completed steps)",
}


def exit_codes_text() -> str:
    """The exit-code table as help text."""
    return "exit codes:\n" + "\n".join(f"  {code:>3}  {text}" for code, text in EXIT_CODES.items())


def parser(prog: str, description: str, examples: Sequence[str]) -> argparse.ArgumentParser:
    """An ArgumentParser with ``--version``, the exit codes and the examples in its help (the project's style)."""
    epilog = "examples:\n" + "\n".join(f"  {e}" for e in examples) + "\n\n" + exit_codes_text()
    ap = ArgumentParser(prog=prog, description=description, epilog=epilog,
                        formatter_class=argparse.RawDescriptionHelpFormatter)  # one-line argument errors, exit 2
    ap.add_argument("--version", action="version", version=version_text(prog))
    return ap


#: wrlayer sub-command -> (module whose ``main(argv)`` runs it, arguments put before the user's).
COMMANDS = {
    "simulate": ("contact.__main__", ["simulate"], "run one contact scene (Kik-Piotrowski or wheel-rail)"),
    "simulate-all": ("contact.__main__", ["simulate-all"], "run every scene of a folder and print a Table 1"),
    "wear": ("contact.__main__", ["wear"], "wear simulation: profiles evolving by wear and inelastic displacement"),
    "calibrate": ("calibration.__main__", ["run"], "FEM calibration of layer tables from a TOML configuration"),
    "rolling": ("calibration.__main__", ["rolling"], "moving-load elastoplastic FEM, pass after pass (rolling)"),
    "mesh": ("meshes.__main__", ["mesh"], "mesh a profile section (2D) or local block (3D)"),
    "mesh-plots": ("meshes.__main__", ["plots"], "pictures of the default meshes"),
}


def _top_parser() -> argparse.ArgumentParser:
    ap = parser("wrlayer", "FEM-calibrated Prandtl surface layers for wheel/rail contact (units mm, N, MPa, s).",
                ["wrlayer simulate scenes/paper_with_layer.toml --out out/one --plots",
                 "wrlayer calibrate calibration/configs/test_coarse.toml --out out/cal",
                 "wrlayer simulate --help"])
    ap.add_argument("command", choices=sorted(COMMANDS), metavar="COMMAND",
                    help="; ".join(f"{k}: {v[2]}" for k, v in COMMANDS.items()))
    ap.add_argument("args", nargs=argparse.REMAINDER, help="arguments of the command (see wrlayer COMMAND --help)")
    return ap


def main(argv: Sequence[str] | None = None) -> int:
    """The ``wrlayer`` console command: dispatch to the package entry points."""
    argv = list(sys.argv[1:] if argv is None else argv)
    args = _top_parser().parse_args(argv[:1] if argv and not argv[0].startswith("-") else argv)
    module, prefix, _ = COMMANDS[args.command]
    return int(importlib.import_module(module).main(prefix + argv[1:]) or 0)


if __name__ == "__main__":
    sys.exit(main())


def subparser(sub, name: str, help: str, examples: Sequence[str]) -> argparse.ArgumentParser:
    """A sub-command parser in the project's style (its examples and the exit codes in its help)."""
    epilog = "examples:\n" + "\n".join(f"  {e}" for e in examples) + "\n\n" + exit_codes_text()
    return sub.add_parser(name, help=help, description=help, epilog=epilog,
                          formatter_class=argparse.RawDescriptionHelpFormatter)
