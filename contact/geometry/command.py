"""``wrlayer geometry``: the contact geometry of a wheel/rail profile pair on a track (Delta r, contact angles, roll,
contact positions and jumps, equivalent conicity after EN 15302), as CSV tables and pictures.

Registered by the package's command line with :func:`add_parser`; runnable on its own as
``python -m contact.geometry.command geometry ...``. Reference: docs/geometry.md.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from contact.geometry.defaults import DEFAULT_AMPLITUDES_MM, DEFAULT_JUMP_MM, DEFAULT_LATERAL_MM, DEFAULT_STEP_MM
from wrlayer import cli
from wrlayer.errors import InputError, cli_guard

if TYPE_CHECKING:
    from meshes.profiles import Profile

EXAMPLES = ["wrlayer geometry --rail 60E1 --wheel S1002 --out out/geometry",
            "wrlayer geometry --rail rail.prr --wheel worn.whl --gauge-mm 1437 --inclination 20 --out out/worn"]
#: Smallest n of an inclination 1:n (0: upright rails), as the scene key ``track.inclination``.
MIN_INCLINATION_RATIO = 5.0
#: The options that are fields of :class:`contact.wheel_rail.track_geometry.TrackLayout` (None: its default).
TRACK_OPTIONS = ("gauge_mm", "gauge_depth_mm", "back_to_back_mm", "flange_back_y_mm", "nominal_radius_mm")


def add_parser(sub) -> None:
    """The ``geometry`` sub-command on the sub-parsers ``sub``."""
    p = cli.subparser(sub, "geometry", "contact geometry of a wheel/rail profile pair: Delta r, contact angles, "
                      "roll, contact points and jumps, equivalent conicity (EN 15302)", EXAMPLES)
    p.add_argument("--rail", required=True, help="rail profile: 60E1, 54E1 or a file (.prr, .txt, .csv, .ban)")
    p.add_argument("--wheel", required=True, help="wheel profile: S1002 or a file (.prw, .txt, .csv, .whl)")
    p.add_argument("--left-rail", default=None, help="left rail profile when it differs (default: --rail)")
    p.add_argument("--left-wheel", default=None, help="left wheel profile when it differs (default: --wheel)")
    p.add_argument("--units", choices=("mm", "m"), default=None,
                   help="length unit of the profile files, all of them (default mm; SIMPACK files state "
                        "their own; standard profiles are not affected)")
    cli.add_profile_check_option(p)
    track = "; default: the standard track, docs/geometry.md"  # TrackLayout's defaults, read when the command runs
    p.add_argument("--gauge-mm", type=float, default=None, help=f"track gauge (mm{track})")
    p.add_argument("--gauge-depth-mm", type=float, default=None,
                   help=f"depth of the gauge point below the rail top (mm{track})")
    p.add_argument("--inclination", type=float, default=None,
                   help="rail inclination 1:n, give n (default 40; 0: upright rails)")
    p.add_argument("--inclination-rad", type=float, default=None, help="rail inclination in rad (instead of 1:n)")
    p.add_argument("--back-to-back-mm", type=float, default=None,
                   help=f"distance between the flange backs (mm{track})")
    p.add_argument("--flange-back-y-mm", type=float, default=None,
                   help=f"wheel profile coordinate of the flange back (mm{track}, S1002)")
    p.add_argument("--nominal-radius-mm", type=float, default=None,
                   help=f"rolling radius at the wheel profile's y = 0 (mm{track})")
    p.add_argument("--lateral-mm", type=float, nargs=2, default=list(DEFAULT_LATERAL_MM), metavar=("MIN", "MAX"),
                   help="lateral displacements of the wheelset (default %(default)s mm)")
    p.add_argument("--step-mm", type=float, default=DEFAULT_STEP_MM, help="lateral step (default %(default)g mm)")
    p.add_argument("--amplitudes-mm", type=float, nargs="+", default=list(DEFAULT_AMPLITUDES_MM),
                   help="amplitudes of the equivalent conicity (default 0.5 .. 10 mm in 0.5 mm steps)")
    p.add_argument("--jump-mm", type=float, default=DEFAULT_JUMP_MM,
                   help="contact-point travel per step reported as a jump (default %(default)g mm)")
    p.add_argument("--no-roll", action="store_true", help="no roll: each wheel lowered onto its rail on its own "
                                                          "(default: the rigid wheelset rolled until both touch)")
    p.add_argument("--no-plots", action="store_true", help="do not write PNG pictures")
    p.add_argument("--out", required=True, help="output folder (geometry.csv, conicity.csv, PNG pictures)")
    p.set_defaults(func=run)


def _profile(name: str | None, body: str, option: str, args) -> Profile | None:
    from meshes.profiles import BUILTIN_PROFILES, named_profile  # the profile modules when the command runs

    if name is None:
        return None
    if name.strip().upper() not in BUILTIN_PROFILES and not Path(name).is_file():
        raise InputError(option, f"no such profile file {name!r}")
    try:  # --units is the files' unit: a standard profile has none
        return named_profile(name, body, args.units, args.accept_unusual_profile)
    except InputError as err:
        raise InputError(option, err.problem if err.what == "profile" else str(err)) from None


def _inclination(args) -> float:
    if args.inclination is not None and args.inclination_rad is not None:
        raise InputError("--inclination", "give either --inclination (1:n) or --inclination-rad, not both")
    if args.inclination_rad is not None:
        return args.inclination_rad
    ratio = 40.0 if args.inclination is None else args.inclination
    if ratio == 0.0:
        return 0.0
    if not (math.isfinite(ratio) and ratio >= MIN_INCLINATION_RATIO):
        raise InputError("--inclination", f"1:n needs n >= {MIN_INCLINATION_RATIO:g} (or 0 for upright rails), "
                                          f"got {ratio:g}")
    from meshes.profiles.placement import rail_inclination

    return rail_inclination(ratio)


def run(args) -> int:
    """Run the analysis of the parsed arguments; write the tables and pictures; print the key numbers."""
    from contact.geometry.analysis import contact_geometry  # the solvers once the arguments are parsed
    from contact.geometry.outputs import write_geometry
    from contact.geometry.sweep import WheelsetProfiles
    from contact.wheel_rail.track_geometry import TrackLayout

    profiles = WheelsetProfiles(_profile(args.rail, "rail", "--rail", args),
                                _profile(args.wheel, "wheel", "--wheel", args),
                                _profile(args.left_rail, "rail", "--left-rail", args),
                                _profile(args.left_wheel, "wheel", "--left-wheel", args))
    given = {name: getattr(args, name) for name in TRACK_OPTIONS if getattr(args, name) is not None}
    layout = TrackLayout(inclination_rad=_inclination(args), **given)
    result = contact_geometry(profiles, layout, args.lateral_mm[0], args.lateral_mm[1], args.step_mm,
                              args.amplitudes_mm, args.jump_mm, with_roll=not args.no_roll)
    paths = write_geometry(result, args.out, pictures=not args.no_plots)
    print(repr(result))
    for line in result.summary_lines():
        print("  " + line)
    print(f"wrote {', '.join(p.name for p in paths)} in {args.out}")
    return 0


@cli_guard
def main(argv: Sequence[str] | None = None) -> int:
    """``python -m contact.geometry.command geometry ...`` (the same sub-command as ``wrlayer geometry``)."""
    parser = cli.parser("python -m contact.geometry.command", "wheel/rail contact geometry", EXAMPLES)
    add_parser(parser.add_subparsers(dest="command", required=True))
    args = parser.parse_args(argv)
    return args.func(args)


if __name__ == "__main__":
    sys.exit(main())


__all__ = ["add_parser", "main", "run"]
