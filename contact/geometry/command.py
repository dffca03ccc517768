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

from contact.geometry.analysis import DEFAULT_LATERAL_MM, contact_geometry
from contact.geometry.conicity import DEFAULT_AMPLITUDES_MM
from contact.geometry.jumps import DEFAULT_JUMP_MM
from contact.geometry.sweep import DEFAULT_STEP_MM, WheelsetProfiles
from contact.wheel_rail.track_geometry import TrackLayout
from meshes.profiles import BUILTIN_PROFILES, Profile, load_profile
from meshes.profiles.placement import rail_inclination
from wrlayer import cli
from wrlayer.errors import InputError, cli_guard

EXAMPLES = ["wrlayer geometry --rail 60E1 --wheel S1002 --out out/geometry",
            "wrlayer geometry --rail rail.prr --wheel worn.whl --gauge-mm 1437 --inclination 20 --out out/worn"]
#: Smallest n of an inclination 1:n (0: upright rails), as the scene key ``track.inclination``.
MIN_INCLINATION_RATIO = 5.0


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
    p.add_argument("--accept-unusual-profile", action="store_true",
                   help="skip the plausibility checks of profile files (a profile unusual on purpose)")
    lay = TrackLayout()
    p.add_argument("--gauge-mm", type=float, default=lay.gauge_mm, help="track gauge (default %(default)g mm)")
    p.add_argument("--gauge-depth-mm", type=float, default=lay.gauge_depth_mm,
                   help="depth of the gauge point below the rail top (default %(default)g mm)")
    p.add_argument("--inclination", type=float, default=None,
                   help="rail inclination 1:n, give n (default 40; 0: upright rails)")
    p.add_argument("--inclination-rad", type=float, default=None, help="rail inclination in rad (instead of 1:n)")
    p.add_argument("--back-to-back-mm", type=float, default=lay.back_to_back_mm,
                   help="distance between the flange backs (default %(default)g mm)")
    p.add_argument("--flange-back-y-mm", type=float, default=lay.flange_back_y_mm,
                   help="wheel profile coordinate of the flange back (default %(default)g mm, S1002)")
    p.add_argument("--nominal-radius-mm", type=float, default=lay.nominal_radius_mm,
                   help="rolling radius at the wheel profile's y = 0 (default %(default)g mm)")
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
    if name is None:
        return None
    if name.strip().upper() in BUILTIN_PROFILES:  # --units is the files' unit: a standard profile has none
        prof = load_profile(name)
    else:
        path = Path(name)
        if not path.is_file():
            raise InputError(option, f"no such profile file {name!r}")
        opts = {"units": args.units, "body": body, "accept_unusual": args.accept_unusual_profile}
        try:
            prof = load_profile(path, **{k: v for k, v in opts.items() if v is not None})
        except InputError as err:
            raise InputError(option, str(err)) from None
    if prof.body != body:
        raise InputError(option, f"{prof.name} is a {prof.body} profile, expected a {body} profile")
    return prof


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
    return rail_inclination(ratio)


def run(args) -> int:
    """Run the analysis of the parsed arguments; write the tables and pictures; print the key numbers."""
    from contact.geometry.outputs import write_geometry  # matplotlib only when writing

    profiles = WheelsetProfiles(_profile(args.rail, "rail", "--rail", args),
                                _profile(args.wheel, "wheel", "--wheel", args),
                                _profile(args.left_rail, "rail", "--left-rail", args),
                                _profile(args.left_wheel, "wheel", "--left-wheel", args))
    layout = TrackLayout(gauge_mm=args.gauge_mm, gauge_depth_mm=args.gauge_depth_mm, inclination_rad=_inclination(args),
                         back_to_back_mm=args.back_to_back_mm, flange_back_y_mm=args.flange_back_y_mm,
                         nominal_radius_mm=args.nominal_radius_mm)
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
