"""Default tolerances stored in FreeCAD's parameter tree (the preferences page edits them).

Group: ``User parameter:BaseApp/Preferences/Mod/ProgSurf``. A value of 0 for FilterThreshold,
SnapTolerance or FitTolerance means "automatic" (the pipeline chooses from the sketch size).
"""
from __future__ import annotations

from dataclasses import dataclass

import FreeCAD

PARAM_PATH = "User parameter:BaseApp/Preferences/Mod/ProgSurf"

DEFAULTS = {"FilterThreshold": 0.0, "SnapTolerance": 0.0, "FitTolerance": 0.0}
"""Float defaults in mm; 0 = automatic (relative to the sketch's size)."""

DEFAULT_SAMPLES = 101
"""Points per stroke taken from a sketch chain or edges (the StrokeSamples parameter)."""


@dataclass(frozen=True)
class DefaultTolerances:
    """The user's default tolerances in mm (0 = automatic)."""

    filter_mm: float
    snap_mm: float
    fit_mm: float
    samples: int


def default_tolerances() -> DefaultTolerances:
    """Read the defaults from the parameter group; missing entries fall back to DEFAULTS."""
    grp = FreeCAD.ParamGet(PARAM_PATH)
    fit = grp.GetFloat("FitTolerance", DEFAULTS["FitTolerance"])
    return DefaultTolerances(
        filter_mm=max(0.0, grp.GetFloat("FilterThreshold", DEFAULTS["FilterThreshold"])),
        snap_mm=max(0.0, grp.GetFloat("SnapTolerance", DEFAULTS["SnapTolerance"])),
        fit_mm=max(0.0, fit),
        samples=max(2, grp.GetInt("StrokeSamples", DEFAULT_SAMPLES)),
    )
