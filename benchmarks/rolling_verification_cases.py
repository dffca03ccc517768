"""The cases of the rolling verification (benchmarks/bench_rolling_verification.py), each run once and cached.

A case is one load level on one block, rolled pass after pass with plain steps (substeps = 1) or with material
sub-steps along the load's path (:mod:`calibration.rolling.substeps`). Its result (groove, surface shift and
largest plastic strain per pass, time per pass, the static dent when asked) is written to ``DIR/<name>.json``
as soon as it is complete, and read back instead of being run again: a killed run keeps its completed cases.
Cases on the same block share one model (mesh, kept factorisation, unit responses). Units mm, MPa, s.
"""

from __future__ import annotations

import json
import os
import time
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import numpy as np

from calibration.fem.solver_state import SolverState
from calibration.rolling.config import (ContactSettings, RollingConfig, RollingMaterial, RollingRunSettings,
                                        TrackMeshSettings, TrackSettings)
from calibration.rolling.groove import GrooveProfile
from calibration.rolling.passes import MovingLoadPass, roll
from calibration.rolling.run import RollingModel, build_model, level_pressures, static_dents
from calibration.rolling.substeps import SubstepSolver, UnitResponses
from calibration.rolling.track_mesh import track_mesh
from wrlayer.atomic_write import atomic_write_text


@dataclass(frozen=True)
class Case:
    """One rolling run: block (model "2d"/"3d", elements per semi-axis n, block size in a, track length in
    contact lengths), load (level in ``unit``: "p_y" or "k"), steps (step in a, material sub-steps, the load
    steps ``ramp`` in which p0 is applied at the track's start), passes,
    isotropic hardening (MPa) and whether the static dent is measured. a = 1 mm, E 210 GPa, nu 0.3, Y 500 MPa."""

    name: str
    model: str
    level: float
    unit: str = "p_y"
    n: float = 3.0
    size: float = 5.0
    length: float = 2.0
    step: float = 0.25
    substeps: int = 1
    ramp: int = 4
    passes: int = 1
    H_iso_MPa: float = 0.0
    static: bool = False

    def config(self) -> RollingConfig:
        return RollingConfig(material=RollingMaterial(H_iso_MPa=self.H_iso_MPa),
                             contact=ContactSettings(a_mm=1.0, levels=(self.level,), model=self.model,
                                                     level_unit=self.unit),
                             track=TrackSettings(length_factor=self.length, step_factor=self.step,
                                                 n_passes=self.passes, ramp_steps=self.ramp),
                             mesh=TrackMeshSettings(elements_per_semi_axis=self.n, size_factor=self.size),
                             run=RollingRunSettings(plots=False, linear_solver="auto"))

    def block_key(self) -> tuple:
        return (self.model, self.n, self.size, self.length, self.H_iso_MPa)


@dataclass(frozen=True)
class VerificationResult:
    """What a case measured: p_y and p0 (MPa), dofs, static dent (mm; 0 when not measured), per pass the groove,
    surface shift (mm), largest equivalent plastic strain (-), the largest NET plastic strain change of the pass
    (-, the equivalent measure sqrt(2/3 de:de) of the plastic strain tensor's change below |x| <= a: zero for a
    closed plastic cycle, the ratchet strain otherwise), wall and process CPU time (s) and Newton iterations; the
    machine's load average (1 / 5 / 15 min) at the start."""

    case: Case
    p_y_MPa: float
    p0_MPa: float
    n_dofs: int
    static_dent_mm: float = 0.0
    groove_mm: list[float] = field(default_factory=list)
    shift_mm: list[float] = field(default_factory=list)
    max_eq_plastic_strain: list[float] = field(default_factory=list)
    net_plastic_increment: list[float] = field(default_factory=list)
    pass_seconds: list[float] = field(default_factory=list)
    pass_cpu_seconds: list[float] = field(default_factory=list)
    newton_iterations: list[int] = field(default_factory=list)
    load_average: list[float] = field(default_factory=list)

    def with_pass(self, prof: GrooveProfile, net: float, rec: MovingLoadPass, cpu_s: float) -> VerificationResult:
        """This result with one more pass: its groove profile, net plastic change (-) and record, CPU time (s)."""
        return replace(self, groove_mm=self.groove_mm + [prof.groove_mm], shift_mm=self.shift_mm + [prof.shift_mm],
                       max_eq_plastic_strain=self.max_eq_plastic_strain + [prof.max_eq_plastic_strain],
                       net_plastic_increment=self.net_plastic_increment + [net],
                       pass_seconds=self.pass_seconds + [rec.seconds],
                       pass_cpu_seconds=self.pass_cpu_seconds + [cpu_s],
                       newton_iterations=self.newton_iterations + [rec.newton_iters])

    def to_dict(self) -> dict:
        return asdict(self)

    @classmethod
    def from_dict(cls, d: dict) -> VerificationResult:
        return cls(**{**d, "case": Case(**d["case"])})


class CaseRunner:
    """Runs cases into ``out_dir`` (cached per case); keeps the model of the last block."""

    def __init__(self, out_dir: Path, progress=print):
        self.out_dir = Path(out_dir)
        self.out_dir.mkdir(parents=True, exist_ok=True)
        self.progress = progress
        self.key, self.model, self.responses = None, None, None
        self.dents: dict[tuple, float] = {}

    def block(self, case: Case) -> RollingModel:
        if case.block_key() != self.key:
            cfg = case.config()
            self.model = build_model(cfg, track_mesh(cfg.contact, cfg.track, cfg.mesh))
            self.responses = UnitResponses(self.model.prob, self.model.forces)
            self.key = case.block_key()
        return self.model

    def __call__(self, case: Case) -> VerificationResult:
        path = self.out_dir / f"{case.name}.json"
        if path.exists():
            res = VerificationResult.from_dict(json.loads(path.read_text()))
            if res.case == case:
                return res
        res = self.run(case)
        atomic_write_text(path, json.dumps(res.to_dict(), indent=1))
        return res

    def run(self, case: Case) -> VerificationResult:
        load = list(os.getloadavg())
        cfg = case.config()
        model = self.block(case)
        p0 = level_pressures(cfg, model.p_y_MPa)[0]
        dent = 0.0
        if case.static:
            key = (case.block_key(), round(p0, 6))
            if key not in self.dents:
                self.dents[key] = static_dents(model, cfg, [p0])[0].dent_mm
            dent = self.dents[key]
        res = VerificationResult(case, model.p_y_MPa, p0, int(model.disc.n_dofs), dent, load_average=load)
        solver = SubstepSolver(model.prob, model.forces, p0, case.substeps, responses=self.responses)
        positions = [x * cfg.contact.a_mm for x in cfg.track.positions_over_a()]
        t0 = time.perf_counter()
        below = model.probe.below
        previous = SolverState.virgin(model.disc).plastic_strain[below]
        cpu = time.process_time()
        for rec in roll(solver, SolverState.virgin(model.disc), positions, case.passes, cfg.track.ramp_steps):
            if isinstance(rec, MovingLoadPass):
                prof = model.probe.profile(rec.state)
                change = rec.state.plastic_strain[below] - previous
                net = float(np.sqrt(2.0 / 3.0 * (change ** 2).sum(axis=-1)).max())
                res = res.with_pass(prof, net, rec, time.process_time() - cpu)
                previous, cpu = rec.state.plastic_strain[below], time.process_time()
                self.progress(f"[{case.name}] pass {rec.pass_index}: groove {prof.groove_mm:.6g} mm, shift "
                              f"{prof.shift_mm:.4g} mm, eq {prof.max_eq_plastic_strain:.4g}, {rec.seconds:.1f} s")
        model.prob.reset_to_elastic()
        self.progress(f"[{case.name}] done in {time.perf_counter() - t0:.0f} s")
        return res


__all__ = ["Case", "VerificationResult", "CaseRunner"]
