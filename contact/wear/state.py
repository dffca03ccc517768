"""What one wear step hands to the next (units mm, MPa; distances in km): the current profiles, the layer state
(largest peak pressure per profile position, :mod:`contact.wear.layer_state`), the tables recalibrated on the worn
profiles (:mod:`contact.wear.recalibrate`), the distance run and the number of completed steps.

Between steps the dent of the inelastic displacement is part of the new profile; the layer state is kept per
profile position (``layer_state = "hardening"``, the default): every position remembers the largest peak pressure
it has carried and its element is hardened to it, so a later step adds a residual only where the load exceeds
that. With ``layer_state = "virgin"`` the elements start virgin on the dented profile every step (the paper's mode
for its 19 passes). ``passes.hardening`` applies within a step's passes. Either way the inelastic part saturates
while wear goes on.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

from calibration.similarity.anchor import DirectReference
from wrlayer.layer_table import LayerTable
from contact.wear.layer_state import History, virgin_history
from contact.wear.planning import distance_left
from contact.wear.records import Profiles, StepRecord
from contact.wear.scene import WearScene


@dataclass(frozen=True)
class WearState:
    """The loop's state before a step.

    Attributes
    ----------
    profiles : dict
        ``profiles[side][body]``: the current profiles.
    history : dict
        ``history[(side, body)]`` = (profile y of the initial profile's grid (mm), largest peak pressure carried so
        far (MPa)).
    tables : dict
        ``tables[(side, body)]``: layer tables recalibrated on the worn profiles (empty: the scene's tables).
    anchors : dict
        ``anchors[side][(body, y)]``: the direct FEM references of the side's recalibration by similarity
        (:mod:`contact.wear.recalibrate`; a side not listed: the scene tables').
    done_km : float
        Running distance of the completed steps (km).
    steps_done : int
        Number of completed steps.
    """

    profiles: Profiles
    history: History
    tables: dict[tuple[str, str], LayerTable] = field(default_factory=dict)
    anchors: dict[str, dict[tuple[str, float], DirectReference]] = field(default_factory=dict)
    done_km: float = 0.0
    steps_done: int = 0

    @classmethod
    def initial(cls, scene: WearScene, profiles: Profiles) -> WearState:
        """Before the first step: the initial ``profiles``, no load carried, the scene's tables."""
        return cls(profiles, virgin_history(profiles, scene.settings.grid_mm))

    def after(self, record: StepRecord, history: History) -> WearState:
        """The state after the completed step ``record`` whose layer state is ``history``."""
        return dataclasses.replace(self, profiles=record.profiles, history=history,
                                   done_km=self.done_km + record.length_km, steps_done=self.steps_done + 1)

    def unfinished(self, scene: WearScene) -> bool:
        """True while the collective's distance has not been run."""
        return distance_left(scene.collective, self.done_km)


__all__ = ["WearState"]
