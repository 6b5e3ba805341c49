"""Helpers every GUI module may import: messages to the user, file dialogs, icon and .ui paths.

This module imports no other ProgSurf.gui module, so that no two GUI modules need to import
each other (STYLE.md).

Dialogs are drivable without interaction: a test sets ``ANSWERS["open"]`` / ``ANSWERS["save"]``
to a path (used once instead of the file dialog) or ``ANSWERS[<question>]`` to True/False (used
once instead of asking), and reads messages from ``MESSAGES`` when ``INTERACTIVE`` is False.
"""
from __future__ import annotations

import os

import FreeCAD
import FreeCADGui

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
RESOURCES = os.path.join(ROOT, "resources")
ICONS = os.path.join(RESOURCES, "icons")
UI_DIR = os.path.join(RESOURCES, "ui")

INTERACTIVE = True
ANSWERS: dict = {}
MESSAGES: list = []


def icon(name: str) -> str:
    """Absolute path of resources/icons/<name>.svg."""
    return os.path.join(ICONS, f"{name}.svg")


def tell(title: str, text: str, error: bool = True) -> None:
    """Report to the user: Report view always, a message box when interactive."""
    (FreeCAD.Console.PrintError if error else FreeCAD.Console.PrintMessage)(
        f"ProgSurf: {text}\n")
    MESSAGES.append((title, text))
    if INTERACTIVE:
        from PySide import QtGui

        box = QtGui.QMessageBox.critical if error else QtGui.QMessageBox.information
        box(FreeCADGui.getMainWindow(), title, text)


def ask_path(kind: str, caption: str, file_filter: str) -> str:
    """A file path from the test hook ANSWERS[kind], else from a file dialog ('' = cancel)."""
    if kind in ANSWERS:
        return ANSWERS.pop(kind)
    from PySide import QtGui

    dialog = QtGui.QFileDialog.getOpenFileName if kind == "open" else \
        QtGui.QFileDialog.getSaveFileName
    path, _ = dialog(FreeCADGui.getMainWindow(), caption, "", file_filter)
    return path


def ask_yes_no(kind: str, title: str, text: str, default: bool) -> bool:
    """A yes/no answer from the test hook ANSWERS[kind], else from a question box (the default
    button is ``default``); without interaction the question goes to MESSAGES and the answer is
    ``default``."""
    if kind in ANSWERS:
        return bool(ANSWERS.pop(kind))
    if not INTERACTIVE:
        MESSAGES.append((title, text))
        return default
    from PySide import QtGui

    buttons = QtGui.QMessageBox.Yes | QtGui.QMessageBox.No
    answer = QtGui.QMessageBox.question(FreeCADGui.getMainWindow(), title, text, buttons,
                                        QtGui.QMessageBox.Yes if default else QtGui.QMessageBox.No)
    return answer == QtGui.QMessageBox.Yes
