"""Recalibration of the layer tables on the worn profiles during a wear run (units mm, N, MPa).

The layer characteristics depend on the local geometry (the paper: they vary along the profile and must come from
FEM on the actual sections), so after wear has changed a profile its tables can be recomputed. With
``[wear.recalibrate] config = "template.toml", every_steps = N`` the loop, after every N-th step and for every
simulated side, recalibrates the bodies of the template on that side's current profiles.

The template is a calibration configuration (:mod:`calibration.config`) whose ``profile`` or ``mate`` entries of
``[[bodies]]`` may name a worn profile by a placeholder, ``@wheel_profile@`` or ``@rail_profile@`` (e.g.
``profile = "@wheel_profile@"``, ``mate = "@rail_profile@"``). It is read and validated once, when the scene is
parsed, with the scene's initial profiles in place of the placeholders (:func:`read_template`): a bad template is an
InputError before the first wear step. At a recalibration the current profiles are written as SIMPACK files into
the step's folder, put in place of the placeholders and the calibration is run in this process
(:func:`calibration.calibrate`, on its ``[run] workers`` or on the Dask cluster of
``wear.scheduler``). The tables it writes replace the scene's tables of that side from the next step on; the
layer state (largest load per position) is kept. A failed calibration (its InputError or ConvergenceError) stops
the loop naming the step; positions that failed inside a table are listed by it and the solver refuses to
interpolate across them.

With ``[run] method = "similarity"`` in the template (:mod:`calibration.similarity`) the recalibration computes no
FEM once the template's master exists (``run.master_dir``; the first recalibration computes it when it is
missing): every position of the template and of the scene's table on the worn profiles gets its characteristic
from the master, in milliseconds; a position outside the master's domain (a patch reaching past the profile's end, a convexity beyond
the master's) from the master's nearest point (``run.similarity_outside = "nearest"``), the reason in the entry's
``warnings``. Only a position without a contact geometry on the worn profile keeps the scene table's entry, marked
in its ``warnings``. Every recalibrated table carries
the scene table's rolling law (:func:`calibration.tables.with_rolling_law`), so the passes keep the rolling memory.
"""

from __future__ import annotations

import dataclasses
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from calibration.config import BodySettings, CalibrationConfig, parse_config, profile_of
from calibration.cost import calibration_cost
from calibration.pipeline import calibrate
from calibration.similarity.anchor import DirectReference, table_references
from calibration.similarity.route import METHOD_SIMILARITY
from calibration.tables import with_rolling_law
from calibration.tasks import make_tasks
from wrlayer.layer_table import LayerTable
from meshes.profiles import Profile
from meshes.profiles.io import parse_simpack, write_simpack
from wrlayer import input_files
from wrlayer.cost import guard
from wrlayer.errors import ConvergenceError, InputError

#: The placeholder of each body's worn profile in a template's ``profile`` and ``mate`` entries.
PLACEHOLDERS = {"wheel": "@wheel_profile@", "rail": "@rail_profile@"}
#: Keys of a ``[[bodies]]`` entry that may hold a placeholder.
PROFILE_KEYS = ("profile", "mate")
SUFFIX = {"wheel": "prw", "rail": "prr"}
#: Largest difference (mm) between the points of two sides' worn profile files for which the later side takes the
#: earlier's recalibration: the round-off of a mirror-symmetric run (1e-14 mm measured), far below a step's wear.
SAME_PROFILE_MM = 1e-9


@dataclass(frozen=True)
class Recalibration:
    """The ``[wear.recalibrate]`` table: a calibration template run on the worn profiles every few steps.

    Attributes
    ----------
    config : str
        The calibration template file (resolved path; given relative to the scene file's folder).
    template : str
        The template's text as read (recorded in result.json; not a scene key).
    calibration : CalibrationConfig
        The validated template; its ``profile``/``mate`` entries hold the placeholders where the worn profiles go
        (not a scene key).
    every_steps : int
        Recalibrate after every this many wear steps (>= 1; not after the last step).
    scene_tables : dict
        The scene's ``[layers]`` table of each body (LayerTable): under ``run.method = "similarity"`` a position
        without a contact geometry on the worn profile keeps its entry from it (not a scene key).
    anchors : dict
        {(body, y): :class:`calibration.similarity.anchor.DirectReference`}: the direct FEM entries of the scene's
        tables calibrated on the scene's initial profiles (the table's profile named as the scene's); under
        ``run.method = "similarity"`` each anchors its position's recalibration (not a scene key).
    reanchor : bool
        Under ``run.method = "similarity"``: a position whose worn patch has left its anchor's (about one master
        grid cell, :func:`calibration.similarity.anchor.applies`) is computed by the direct FEM, and that entry
        anchors the side's later recalibrations; false (default): such a position is served by the master alone
        (the wear example: x1.18 the run without recalibration, docs/validation/similarity.md; with re-anchoring x4.3 in
        an earlier run, 6 FEM positions).
    """

    config: str
    template: str
    calibration: CalibrationConfig
    every_steps: int = 1
    scene_tables: dict[str, LayerTable] = field(default_factory=dict)
    anchors: dict[tuple[str, float], DirectReference] = field(default_factory=dict)
    reanchor: bool = False

    @property
    def by_similarity(self) -> bool:
        """True when the template calibrates by similarity (every position from the master)."""
        return self.calibration.run.method == METHOD_SIMILARITY

    @property
    def bodies(self) -> tuple[str, ...]:
        """The bodies whose worn profile the template uses (by placeholder)."""
        used = {getattr(b, key) for b in self.calibration.bodies for key in PROFILE_KEYS}
        return tuple(body for body, ph in PLACEHOLDERS.items() if ph in used)

    def due(self, step: int) -> bool:
        """True after the steps at which the tables are recalibrated."""
        return step % self.every_steps == 0


def read_template(path: Path, what: str, profiles: dict[str, Profile], inclination_rad: float
                  ) -> tuple[str, CalibrationConfig]:
    """Read and validate a calibration template (InputError ``what: ...``); returns its text and the config with
    the placeholders kept in its ``profile``/``mate`` entries. Everything the calibration checks before its FEM
    (keys, profiles and positions, each position's contact geometry, mesh settings, the cost guard) is checked here
    with ``profiles[body]`` (the scene's initial profiles) in place of the placeholders. A body with the worn rail
    (a profile file in the rail's own frame) is calibrated at the scene's rail inclination ``inclination_rad`` (rad)
    unless the template gives one."""
    where = f"{what} ({path.name})"
    text = input_files.read_text(path, input_files.MAX_TOML_BYTES, where)  # FIFO, size, UTF-8 (byte offset)
    data = input_files.parse_toml(text, where)
    rows = data.get("bodies") if isinstance(data.get("bodies"), list) else []
    if not any(isinstance(row, dict) and row.get(key) in PLACEHOLDERS.values()
               for row in rows for key in PROFILE_KEYS):
        raise InputError(what, f"{path.name} uses neither placeholder {' nor '.join(PLACEHOLDERS.values())} as a "
                         "[[bodies]] profile or mate (where the worn profile files go)")
    for row in rows:
        if isinstance(row, dict) and PLACEHOLDERS["rail"] in (row.get("profile"), row.get("mate")) and not \
                {"inclination", "inclination_rad", "rail_cant_rad"} & set(row):
            row["inclination_rad"] = float(inclination_rad)  # the worn rail file is in the rail's own frame
    with tempfile.TemporaryDirectory(prefix="wrlayer-template-") as tmp:
        files = write_profiles(profiles, Path(tmp), "initial")
        for row in rows:
            for key in PROFILE_KEYS:
                body = _placeholder_body(row.get(key)) if isinstance(row, dict) else None
                if body is not None:
                    row[key] = str(files[body])
        cfg = parse_config(data, f"{what} ({path.name})", path.parent)
        tasks, failed, _warnings = make_tasks(cfg, Path(tmp), plots=False)  # each position's contact geometry
    if failed:
        raise InputError(f"{what} ({path.name})", f"{failed[0].body} position y = {failed[0].y_mm:g} mm on "
                         f"the initial profiles: {failed[0].message}")
    guard(calibration_cost(cfg, tasks))  # a recalibration refused by its cost would stop the loop late
    cfg = dataclasses.replace(cfg, bodies=tuple(_restore(b, rows[i], files) for i, b in enumerate(cfg.bodies)))
    return text, cfg


def _placeholder_body(value) -> str | None:
    return next((body for body, ph in PLACEHOLDERS.items() if value == ph), None)


def _restore(body: BodySettings, row: dict, files: dict[str, Path]) -> BodySettings:
    """``body`` with the placeholders back in the entries the template gave them (not the validation files)."""
    back = {key: PLACEHOLDERS[b] for key in PROFILE_KEYS for b, f in files.items() if row.get(key) == str(f)}
    return dataclasses.replace(body, **back)


def write_profiles(profiles: dict[str, Profile], folder: Path, label: str) -> dict[str, Path]:
    """Write ``profiles[body]`` (wheel, rail) as SIMPACK files into ``folder``; returns their paths."""
    folder.mkdir(parents=True, exist_ok=True)
    paths = {}
    for body, profile in profiles.items():
        path = folder / f"{body}.{SUFFIX[body]}"
        write_simpack(path, profile, body=body, comment=f"{label} {body} profile for recalibration")
        paths[body] = path.resolve()
    return paths


def worn_config(cfg: CalibrationConfig, files: dict[str, Path]) -> CalibrationConfig:
    """``cfg`` with the placeholders replaced by the worn profile files ``files[body]``."""
    by_placeholder = {PLACEHOLDERS[b]: str(path) for b, path in files.items()}
    bodies = tuple(dataclasses.replace(b, **{key: by_placeholder[getattr(b, key)] for key in PROFILE_KEYS
                                             if getattr(b, key) in by_placeholder}) for b in cfg.bodies)
    return dataclasses.replace(cfg, bodies=bodies)


@dataclass(frozen=True)
class SideTables:
    """One side's recalibration: ``tables`` {body: LayerTable} and ``anchors`` {(body, y): DirectReference}, the
    side's anchors for its next recalibration (those it had, with the positions this one computed by the direct
    FEM on the worn profile, or served with their section's elastic solve, in their place)."""

    tables: dict[str, LayerTable]
    anchors: dict[tuple[str, float], DirectReference]


def recalibrate_side(recal: Recalibration, profiles: dict[str, Profile], work: Path, scheduler: str = "",
                     what: str = "wear.recalibrate",
                     anchors: dict[tuple[str, float], DirectReference] | None = None,
                     files: dict[str, Path] | None = None) -> SideTables:
    """Calibrate the bodies of the template on ``profiles[body]`` (the current profiles of one side, written into
    ``work`` unless ``files`` gives them already written there by :func:`write_profiles`) in ``work``;
    returns the tables of the bodies the template calibrates (by similarity: every position from the master,
    anchored to ``anchors`` (default: the scene tables' ``recal.anchors``), those without a geometry on the worn
    profile kept from the scene's table by :func:`merged_table`) and the side's anchors after it.
    InputError/ConvergenceError ``what: ...``."""
    work = Path(work)
    anchors = recal.anchors if anchors is None else anchors
    files = files if files is not None else write_profiles(profiles, work, "worn")
    _share_cache(work)
    cfg = worn_config(recal.calibration, files)
    try:
        for b in recal.calibration.bodies:  # the template's positions were checked on the initial profiles
            worn = profiles[_placeholder_body(b.profile)] if b.profile in PLACEHOLDERS.values() else None
            for y in b.positions_mm if worn is not None else ():
                worn.check_y(y, f"position y = {y:g} mm on the worn {b.body} profile")
        if recal.by_similarity:  # every position through the master; by the FEM only to re-anchor
            cfg = similarity_config(cfg, recal.scene_tables)
        result = calibrate(cfg, work / "tables", scheduler=scheduler or None, plots=False, show_progress=False,
                           log=_quiet, anchors=anchors if recal.by_similarity else None,
                           reanchor=recal.reanchor) if cfg.bodies else None
    except InputError as err:
        raise InputError(what, f"calibration of the worn profiles failed: {err}") from None
    except ConvergenceError as err:
        raise ConvergenceError(f"{what}: calibration of the worn profiles failed: {err}") from None
    tables = {body: LayerTable.read(path) for body, path in (result.tables.items() if result else ())}
    if recal.by_similarity:  # the positions computed by the FEM, or by their section's elastic solve, on the worn
        # profile anchor the next ones
        anchors = {**anchors, **{key: ref for b in cfg.bodies if b.body in tables
                                 for key, ref in table_references(tables[b.body], profile_of(b.profile)).items()},
                   **(result.section_references if result else {})}
        direct = {(f.body, f.y_mm): f.message for f in (result.failed if result else ())}  # e.g. no geometry
        bodies = {b.body for b in recal.calibration.bodies}
        tables = {body: merged_table(recal.scene_tables[body], tables.get(body), direct)
                  if body in recal.scene_tables else tables[body] for body in bodies
                  if body in recal.scene_tables or body in tables}
    if not tables:
        raise InputError(what, f"the calibration wrote no layer table into {work / 'tables'}: "
                         f"{'; '.join(f.message for f in result.failed) if result else ''}"
                         f"{'' if result and result.failed else 'no position calibrated'}")
    return SideTables({body: with_rolling_law(table, recal.scene_tables.get(body)) for body, table in tables.items()},
                      anchors)


def _share_cache(work: Path) -> None:
    """Point ``work``/tables/cache at ``work``'s parent's ``cache`` folder: one FEM cache for the sides and steps of
    a run, so that a position a mirror-symmetric side shares (the same worn profile file, the same key) is computed
    once (re-anchoring on both sides of the wear example: step 1's two positions computed once for both sides)."""
    shared = work.parent / "cache"
    shared.mkdir(parents=True, exist_ok=True)
    link = work / "tables" / "cache"
    link.parent.mkdir(parents=True, exist_ok=True)
    if not link.exists() and not link.is_symlink():
        link.symlink_to(shared.resolve(), target_is_directory=True)


def similarity_config(cfg: CalibrationConfig, scene_tables: dict[str, LayerTable]) -> CalibrationConfig:
    """``cfg`` recalibrating by similarity every position of the template and of the scene's table of each body
    (the master serves them all in milliseconds), those outside the master's domain from its nearest point."""
    bodies = []
    for b in cfg.bodies:
        table = scene_tables.get(b.body)
        ys = set(b.positions_mm) | ({float(p["y_mm"]) for p in table.positions} if table is not None else set())
        bodies.append(dataclasses.replace(b, positions_mm=tuple(sorted(ys))))
    return dataclasses.replace(cfg, bodies=tuple(bodies),
                               run=dataclasses.replace(cfg.run, similarity_outside="nearest"))


def merged_table(scene: LayerTable, new: LayerTable | None, direct: dict[tuple[str, float], str]) -> LayerTable:
    """The scene's table with the positions of ``new`` (recalibrated by similarity) in place of its own; its other
    entries kept, each with a warning naming why (``direct[(body, y)]``: no geometry on the worn profile)."""
    if new is None:
        new = scene
    fresh = {float(p["y_mm"]) for p in new.positions}
    kept = []
    for p in scene.positions:
        y = float(p["y_mm"])
        if y in fresh:
            continue
        why = direct.get((scene.body, y), "not a position of the template")
        kept.append(dict(p, warnings=list(p.get("warnings", [])) + [
            f"kept from {scene.source}: not recalibrated on the worn profile ({why})"]))
    positions = sorted(list(new.positions) + kept, key=lambda p: float(p["y_mm"]))
    failed = [f for f in new.failed if float(f["y_mm"]) not in {float(p["y_mm"]) for p in kept}]
    return LayerTable(new.header, positions, failed, new.source if new is not scene else f"{scene.source} (kept)")


def recalibrate_sides(recal: Recalibration, profiles: dict[str, dict[str, Profile]], step: int,
                      work_dir: Path | None, scheduler: str = "",
                      anchors: dict[str, dict[tuple[str, float], DirectReference]] | None = None
                      ) -> tuple[dict[tuple[str, str], LayerTable], dict[str, dict[tuple[str, float], DirectReference]]]:
    """The tables of every side recalibrated on its current profiles after ``step``, as {(side, body): table},
    and every side's anchors after it ({side: {(body, y): reference}}; ``anchors``: before it, a side not listed
    starts from the scene tables'); the files go to ``work_dir``/calibration/step_NNN_<side> (default: a new
    temporary folder). A side whose worn profile files and anchors equal an earlier side's (within
    :data:`SAME_PROFILE_MM`: a mirror-symmetric run) takes that side's tables; its folder holds only its profiles."""
    base = Path(work_dir) if work_dir is not None else Path(tempfile.mkdtemp(prefix="wrlayer-recal-"))
    tables, after = {}, {}
    done: list[tuple[dict[str, Path], dict | None, SideTables]] = []
    for side, prof in profiles.items():
        side_anchors = (anchors or {}).get(side)
        work = base / "calibration" / f"step_{step:03d}_{side}"
        files = write_profiles(prof, work, "worn")  # what the calibration reads
        found = next((f for fs, a, f in done if a == side_anchors and same_profile_files(fs, files)), None)
        if found is None:
            found = recalibrate_side(recal, prof, work, scheduler, what=f"step {step}: wear.recalibrate ({side} side)",
                                     anchors=side_anchors, files=files)
        done.append((files, side_anchors, found))
        tables.update({(side, body): table for body, table in found.tables.items()})
        after[side] = found.anchors
    return tables, after


def same_profile_files(a: dict[str, Path], b: dict[str, Path]) -> bool:
    """True when ``a`` and ``b`` ({body: SIMPACK file}, :func:`write_profiles`) hold the same bodies whose points
    agree within :data:`SAME_PROFILE_MM`."""
    if a.keys() != b.keys():
        return False
    for body in a:
        pa, pb = parse_simpack(a[body])[1], parse_simpack(b[body])[1]
        if pa.shape != pb.shape or not np.all(np.abs(pa - pb) <= SAME_PROFILE_MM):
            return False
    return True


def _quiet(message: str) -> None:
    """The calibration's progress lines are not shown inside a wear run (its summary.json records the run)."""


__all__ = ["PLACEHOLDERS", "SAME_PROFILE_MM", "Recalibration", "SideTables", "merged_table", "read_template",
           "recalibrate_side", "recalibrate_sides", "same_profile_files", "similarity_config", "worn_config",
           "write_profiles"]
