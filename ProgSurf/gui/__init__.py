"""ProgSurf GUI layer: commands, view providers, task panels, preferences, analysis view.

The only package that imports FreeCADGui or PySide. InitGui.py calls the two functions below
when the workbench is first activated. Messages, file dialogs, icon and .ui paths live in
``common``, which imports no other GUI module; face colouring lives in ``face_colours``.
"""
from __future__ import annotations

import os


def register_commands() -> list[str]:
    """Register the workbench's commands with FreeCADGui; return their names in toolbar order."""
    from ProgSurf.app import make

    from . import commands, view_providers

    make.VIEW_PROVIDER_HOOK = view_providers.attach
    return commands.register()


def register_preferences() -> None:
    """Register the preferences page of the default tolerances (Edit > Preferences > ProgSurf).

    Values live in ``User parameter:BaseApp/Preferences/Mod/ProgSurf``; make_surface reads them.
    The dialog shows the group with the icon named ``preferences-progsurf`` on the icon path.
    """
    import FreeCADGui

    from .common import ICONS, UI_DIR

    FreeCADGui.addIconPath(ICONS)
    FreeCADGui.addPreferencePage(os.path.join(UI_DIR, "preferences.ui"), "ProgSurf")
