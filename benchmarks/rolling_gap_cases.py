"""The gap cases: the rolling FEM at the half-space and at calibration positions, one JSON file per case (mm, MPa, s).

A position of the default tables (``scenes/tables/*_default.json``) gives the Hertz semi-axes a (rolling direction
x) and b (lateral) of its patch and the calibration's material (mixed hardening); its rolling case is the
half-space block of :mod:`calibration.rolling.track_mesh` with that elliptic patch and material, not the profile
section: the static 3D characteristic does not depend on the support or the section depth (within 0.13 %,
docs/calibration-method.md), and the block's static dent is checked against the table's residual
(docs/rolling-gap.md). The half-space case is the rolling reference's circular patch, elastic-perfectly
plastic. A case is (position, p0 / p_y, traction coefficient c) with ``n_passes`` passes at constant p0; p_y is
the block's own FEM first-yield pressure. Each case is written to ``<out>/<position>_c<c>_p<level>.json`` as
soon as it is done (a killed run keeps its completed cases; a present file is read, not recomputed).

``python -m benchmarks.rolling_gap_cases OUT [--passes N]`` runs every default case (the benchmark's ``gap``
mode reads them); ``--mesh-check`` and ``--shape-check`` run the checks of the mesh correction and of the laws'
patch-shape nodes instead (into ``OUT_mesh`` and ``OUT_shape`` by convention, where the benchmark looks).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

from calibration.rolling.config import (ContactSettings, RollingConfig, RollingMaterial, RollingRunSettings,
                                        TrackMeshSettings, TrackSettings)
from calibration.rolling.passes import MovingLoadPass, RollingConvergenceError, RollingSolver, roll
from calibration.rolling.run import build_model, static_dents
from calibration.rolling.section_position import table_position as position_in_table
from calibration.rolling.track_mesh import track_mesh
from calibration.fem.solver_state import SolverState
from wrlayer.atomic_write import atomic_write_text

ROOT = Path(__file__).resolve().parents[1]
#: The levels p0 / p_y and traction coefficients of the gap.
LEVELS = (1.15, 1.3, 1.5, 1.7, 2.1)
TRACTIONS = (0.0, 0.2)
#: The passes of each case.
N_PASSES = 10
#: The coarse rolling discretisation of every case (h = a / 2 quadratic tetrahedra, step a / 4, track 1.5 contact
#: lengths, block 4 a): about 22,000 dofs and 4-8 s per pass at a/b = 1.33 on the project's machine.
GAP_TRACK = TrackSettings(length_factor=1.5, step_factor=0.25, n_passes=N_PASSES, ramp_steps=2)
GAP_MESH = TrackMeshSettings(elements_per_semi_axis=2.0, size_factor=4.0)


@dataclass(frozen=True)
class GapPosition:
    """Where a case rolls: a name, the table it comes from ("" for the half-space), the profile coordinate
    y_mm (mm), the semi-axes a_mm (rolling direction) and b_mm (mm) and the material."""

    name: str
    table: str
    y_mm: float
    a_mm: float
    b_mm: float
    material: RollingMaterial


#: The half-space of the rolling reference: circular patch a = 1 mm, elastic-perfectly plastic steel.
HALF_SPACE = GapPosition("half-space", "", 0.0, 1.0, 1.0, RollingMaterial())
#: The calibration positions of the gap (table, y in mm, name), as in the calibration's convergence study.
TABLE_POSITIONS = (("scenes/tables/rail_60E1_default.json", 0.0, "rail crown"),
                   ("scenes/tables/rail_60E1_default.json", -35.0, "rail gauge corner"),
                   ("scenes/tables/wheel_S1002_default.json", -37.5, "wheel flange root"),
                   ("scenes/tables/wheel_S1002_default.json", 0.0, "wheel tread"),
                   # the long patches (a/b = 3.83 and 10.2): the laws' further patch-shape nodes
                   ("scenes/tables/rail_60E1_default.json", 25.0, "rail field side"),
                   ("scenes/tables/rail_60E1_default.json", 30.0, "rail field shoulder"))


def table_position(table_rel: str, y_mm: float, name: str) -> GapPosition:
    """The position ``y_mm`` of a shipped table: its patch semi-axes and the table's material."""
    pos = position_in_table(table_rel, y_mm)
    return GapPosition(name, table_rel, y_mm, pos.a_mm, pos.b_mm, RollingMaterial(**asdict(pos.material)))


def default_positions() -> list[GapPosition]:
    """The table positions of the gap and the half-space (the order of the runs: the rail's round patches first,
    the long patch last)."""
    table = [table_position(*t) for t in TABLE_POSITIONS]
    return table[:2] + [HALF_SPACE] + table[2:]


@dataclass(frozen=True)
class GapCase:
    """One rolling case: a position, p0 / p_y (the block's own p_y), the traction coefficient c and the passes."""

    position: GapPosition
    level: float
    traction: float
    n_passes: int = N_PASSES
    elements_per_semi_axis: float = GAP_MESH.elements_per_semi_axis

    @property
    def key(self) -> str:
        mesh = "" if self.elements_per_semi_axis == GAP_MESH.elements_per_semi_axis else \
            f"_h{self.elements_per_semi_axis:g}"
        return f"{self.position.name.replace(' ', '_')}_c{self.traction:g}_p{self.level:g}{mesh}"

    def config(self, track: TrackSettings = GAP_TRACK, mesh: TrackMeshSettings = GAP_MESH) -> RollingConfig:
        mesh = replace(mesh, elements_per_semi_axis=self.elements_per_semi_axis)
        pos = self.position
        contact = ContactSettings(a_mm=pos.a_mm, b_mm=pos.b_mm, levels=(self.level,),
                                  traction_coefficient=self.traction, level_unit="p_y")
        return RollingConfig(contact, pos.material, replace(track, n_passes=self.n_passes), mesh,
                             RollingRunSettings(plots=False), source=self.key)


@dataclass(frozen=True)
class GapCaseResult:
    """The FEM of one case (a file ``<key>.json``).

    Attributes
    ----------
    key : str
        The case's name (position, traction coefficient, level).
    position : str
        Name of the position.
    table : str
        The table the position comes from ("" for the half-space).
    y_mm : float
        Profile coordinate of the position (mm).
    a_mm : float
        Semi-axis along the rolling direction (mm).
    b_mm : float
        Lateral semi-axis (mm).
    traction : float
        Traction coefficient c (-).
    p0_over_py : float
        Peak pressure over the block's FEM first-yield pressure (-).
    p_y_MPa : float
        The block's FEM first-yield pressure of the static load (MPa).
    static_dent_mm : float
        Residual depth of the static indentation (mm).
    static_p_MPa : list of float
        Loading points of the static indentation (MPa).
    static_u_pl_mm : list of float
        Inelastic centre displacement at those points (mm).
    groove_mm : list of float
        Groove after each completed pass (mm, cumulative).
    shift_mm : list of float
        Mean residual surface displacement along x after each pass (mm).
    max_eq_plastic_strain : list of float
        Largest equivalent plastic strain below mid-track after each pass (-).
    pass_seconds : list of float
        Wall time of each pass (s).
    n_dofs : int
        Degrees of freedom of the block.
    failed : str
        The error that stopped the passes ("": none).
    n_passes : int
        Passes requested (the file is rewritten after each pass: fewer grooves when the run was stopped).
    """

    key: str
    position: str
    table: str
    y_mm: float
    a_mm: float
    b_mm: float
    traction: float
    p0_over_py: float
    p_y_MPa: float
    static_dent_mm: float
    static_p_MPa: list[float]
    static_u_pl_mm: list[float]
    groove_mm: list[float] = field(default_factory=list)
    shift_mm: list[float] = field(default_factory=list)
    max_eq_plastic_strain: list[float] = field(default_factory=list)
    pass_seconds: list[float] = field(default_factory=list)
    n_dofs: int = 0
    failed: str = ""
    n_passes: int = N_PASSES

    @property
    def complete(self) -> bool:
        """All requested passes done, or stopped by a failed step."""
        return len(self.groove_mm) >= self.n_passes or bool(self.failed)

    def to_dict(self) -> dict:
        return {k: getattr(self, k) for k in self.__dataclass_fields__}

    @classmethod
    def from_dict(cls, data: dict) -> GapCaseResult:
        return cls(**{k: data[k] for k in cls.__dataclass_fields__ if k in data})


def run_case(case: GapCase, out_dir: Path, progress=None, track: TrackSettings = GAP_TRACK,
             mesh: TrackMeshSettings = GAP_MESH) -> GapCaseResult:
    """The case's result: read from ``out_dir/<key>.json`` when complete there, else computed (on ``track`` and
    ``mesh``, the gap's by default) and written there after every pass."""
    path = Path(out_dir) / f"{case.key}.json"
    if path.exists():
        done = GapCaseResult.from_dict(json.loads(path.read_text()))
        if done.complete:
            return done
    Path(out_dir).mkdir(parents=True, exist_ok=True)
    cfg = case.config(track, mesh)
    model = build_model(cfg, track_mesh(cfg.contact, cfg.track, cfg.mesh))
    p0 = case.level * model.p_y_MPa
    (curve,) = static_dents(model, cfg, [p0])
    pos = case.position
    res = GapCaseResult(case.key, pos.name, pos.table, pos.y_mm, pos.a_mm, pos.b_mm, case.traction, case.level,
                        model.p_y_MPa, curve.dent_mm, curve.p_MPa.tolist(), curve.u_pl_mm.tolist(),
                        n_dofs=int(model.disc.n_dofs), n_passes=case.n_passes)
    positions = [x * cfg.contact.a_mm for x in cfg.track.positions_over_a()]
    solver = RollingSolver(model.prob, model.forces, p0)
    try:
        for rec in roll(solver, SolverState.virgin(model.disc), positions, case.n_passes, cfg.track.ramp_steps):
            if isinstance(rec, MovingLoadPass):
                prof = model.probe.profile(rec.state)
                res = replace(res, groove_mm=res.groove_mm + [prof.groove_mm], shift_mm=res.shift_mm + [prof.shift_mm],
                              max_eq_plastic_strain=res.max_eq_plastic_strain + [prof.max_eq_plastic_strain],
                              pass_seconds=res.pass_seconds + [rec.seconds])
                atomic_write_text(path, json.dumps(res.to_dict(), indent=1))
                if progress is not None:
                    progress(f"{case.key}: pass {rec.pass_index} groove {prof.groove_mm:.5g} mm ({rec.seconds:.1f} s)")
    except RollingConvergenceError as err:
        res = replace(res, failed=str(err))
    atomic_write_text(path, json.dumps(res.to_dict(), indent=1))
    return res


def default_cases(n_passes: int = N_PASSES, levels: tuple[float, ...] = LEVELS) -> list[GapCase]:
    """Every case, position by position (both tractions, the levels)."""
    return [GapCase(pos, lv, c, n_passes) for pos in default_positions() for c in TRACTIONS for lv in levels]


def mesh_check_cases(n_passes: int = 5) -> list[GapCase]:
    """The direct check of the mesh correction (:mod:`benchmarks.rolling_gap_static`) at h = a/4: the rail gauge
    corner at 2.1 p_y (the largest gap on the coarse mesh) frictionless and at 1.7 p_y with c = 0.2, and the
    ratcheting half-space at 2.1 p_y frictionless and at 1.7 p_y with c = 0.2."""
    corner = table_position(*TABLE_POSITIONS[1])
    return [GapCase(corner, 2.1, 0.0, n_passes, 4.0), GapCase(corner, 1.7, 0.2, n_passes, 4.0),
            GapCase(HALF_SPACE, 2.1, 0.0, n_passes, 4.0), GapCase(HALF_SPACE, 1.7, 0.2, n_passes, 4.0)]


#: The check of the laws' patch-shape nodes: blocks at shapes between the nodes (wheel y = -7.5 mm, a/b = 2.36;
#: wheel y = -30 mm, a/b = 5.83), 5 passes (table, y in mm, name, [(c, p0 / p_y)]).
SHAPE_CHECK = (("scenes/tables/wheel_S1002_default.json", -7.5, "wheel tread -7.5",
                ((0.2, 1.3), (0.2, 1.5), (0.2, 2.1), (0.0, 1.5), (0.0, 2.1))),
               ("scenes/tables/wheel_S1002_default.json", -30.0, "wheel flange flank -30",
                ((0.2, 1.5), (0.0, 1.5), (0.2, 2.1))))


def shape_check_cases(n_passes: int = 5) -> list[GapCase]:
    """The cases of :data:`SHAPE_CHECK`."""
    return [GapCase(table_position(table, y, name), lv, c, n_passes)
            for table, y, name, cases in SHAPE_CHECK for c, lv in cases]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m benchmarks.rolling_gap_cases", description=__doc__.splitlines()[0])
    ap.add_argument("out", type=Path)
    ap.add_argument("--passes", type=int, default=N_PASSES)
    ap.add_argument("--levels", type=float, nargs="+", default=list(LEVELS), help="levels p0 / p_y (default: LEVELS)")
    ap.add_argument("--only", nargs="*", default=[], help="run only the positions whose name contains one of these")
    ap.add_argument("--mesh-check", action="store_true", help="run the mesh check cases instead")
    ap.add_argument("--shape-check", action="store_true", help="run the patch-shape check cases instead")
    args = ap.parse_args(argv)
    from threadpoolctl import threadpool_limits  # one BLAS thread on the shared machine

    cases = (mesh_check_cases() if args.mesh_check else shape_check_cases() if args.shape_check
             else default_cases(args.passes, tuple(args.levels)))
    with threadpool_limits(limits=1):
        for case in cases:
            if args.only and not any(name in case.position.name for name in args.only):
                continue
            t0 = time.perf_counter()
            res = run_case(case, args.out, progress=lambda s: print(s, flush=True))
            print(f"{case.key}: done {time.perf_counter() - t0:.0f} s {res.failed}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
