"""Command line of the meshes package (lengths in mm).

    wrlayer mesh-plots --out DIR
        PNG pictures of the default 2D section and 3D local meshes (60E1 rail, S1002 wheel).
    wrlayer mesh PROFILE --y0 Y --h-min H --h-max H [--dim 2|3] [--order 1|2] [--depth D]
                          [--length L] [--refine-radius R] [--refine-box BX BY BZ] [--grading G] --out FILE
        Mesh a profile (standard name such as 60E1, 54E1, S1002, or a profile file) and write FILE (.vtu/.msh).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from wrlayer import cli
from wrlayer.errors import cli_guard


def _parser() -> argparse.ArgumentParser:
    parser = cli.parser("python -m meshes", "Meshes of rail and wheel profiles (lengths in mm).",
                        ["wrlayer mesh 60E1 --y0 0 --h-min 0.5 --h-max 5 --out out/mesh/rail_2d.vtu",
                         "wrlayer mesh-plots --out out/plots"])
    sub = parser.add_subparsers(dest="command", required=True)
    plots = cli.subparser(sub, "plots", "pictures of the default meshes", ["wrlayer mesh-plots --out out/plots"])
    plots.add_argument("--out", required=True, help="output folder for the PNG files")
    mesh = cli.subparser(sub, "mesh", "mesh a profile section (2D) or a local 3D block and write it",
                         ["wrlayer mesh 60E1 --y0 0 --h-min 0.5 --h-max 5 --out out/mesh/rail_2d.vtu",
                          "wrlayer mesh S1002 --y0 0 --h-min 0.5 --h-max 8 --dim 3 --order 2 "
                          "--refine-box 3 4 2 --out out/mesh/wheel.msh"])
    mesh.add_argument("profile", help="60E1, 54E1, S1002 or a profile file (.prr/.prw/.txt/.csv)")
    mesh.add_argument("--y0", type=float, required=True, help="lateral load position y0 (mm)")
    mesh.add_argument("--h-min", type=float, required=True, help="element size at the load point (mm)")
    mesh.add_argument("--h-max", type=float, required=True, help="largest element size (mm)")
    mesh.add_argument("--dim", type=int, choices=(2, 3), default=2, help="2: plane section, 3: local block")
    mesh.add_argument("--order", type=int, default=1, help="element order 1 or 2")
    mesh.add_argument("--depth", type=float, default=None, help="section depth (mm); default rail 60, wheel 40")
    mesh.add_argument("--length", type=float, default=30.0, help="3D: half-model length along x (mm)")
    mesh.add_argument("--refine-radius", type=float, default=0.0, help="2D: radius meshed with h_min (mm)")
    mesh.add_argument("--refine-box", type=float, nargs=3, default=(0.0, 0.0, 0.0), metavar=("BX", "BY", "BZ"),
                      help="3D: half-sizes of the box meshed with h_min (mm)")
    mesh.add_argument("--grading", type=float, default=None, help="size growth per mm of distance (default 0.3)")
    mesh.add_argument("--out", required=True, help="output mesh file (.vtu or .msh)")
    cli.add_profile_check_option(mesh)
    return parser


@cli_guard
def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    if args.command == "plots":
        from meshes.plots import write_default_plots

        for path in write_default_plots(args.out):
            print(path)
        return 0

    from meshes.meshing.local_mesh import local_mesh
    from meshes.meshing.mesh_io import check_mesh_path, write_mesh
    from meshes.meshing.mesh_quality import element_quality
    from meshes.profiles import PROFILE_FILE_SUFFIXES, get_profile
    from meshes.meshing.section_mesh import DEFAULT_GRADING, section_mesh

    check_mesh_path(args.out)
    is_file = Path(args.profile).suffix.lower() in PROFILE_FILE_SUFFIXES
    profile = get_profile(args.profile, **({"accept_unusual": True} if args.accept_unusual_profile and is_file
                                           else {}))
    grading = DEFAULT_GRADING if args.grading is None else args.grading
    start = time.perf_counter()
    if args.dim == 2:
        mesh = section_mesh(profile, args.y0, args.h_min, args.h_max, depth_mm=args.depth, order=args.order,
                            refine_radius_mm=args.refine_radius, grading=grading)
    else:
        mesh = local_mesh(profile, args.y0, args.h_min, args.h_max, length_mm=args.length, depth_mm=args.depth,
                          order=args.order, refine_box=tuple(args.refine_box), grading=grading)
    seconds = time.perf_counter() - start
    path = write_mesh(mesh, args.out)
    print(f"{path}: {type(mesh).__name__}, {mesh.nvertices} vertices, {mesh.doflocs.shape[1]} nodes, "
          f"{mesh.nelements} elements, min quality {element_quality(mesh).min():.3f}, meshed in {seconds:.2f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
