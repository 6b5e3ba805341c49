"""Optional Python packages: imported when a feature needs them, with a message that says how
to get them. Standard library only, so that every layer may use it.

    c3d         reading .c3d motion-capture files (PyPI only, MIT licence)
    matplotlib  pictures: the Analyse view's pre-image plane, the command line's --png

FreeCAD's Addon Manager reads the same list from metadata.txt (``optionalpylibs=``), so that
installing ProgSurf never stops on them. A test keeps the two lists equal.
"""
from __future__ import annotations

import importlib
import importlib.util
import os
import sys
from typing import Optional

from .core.errors import MissingPackageError

OPTIONAL_PACKAGES = {
    "c3d": "the PyPI package 'c3d' (MIT licence, pure Python)",
    "matplotlib": "matplotlib (Debian/Ubuntu: sudo apt install python3-matplotlib)",
}
"""Every optional package ProgSurf imports, with how to name it to a user."""

_NO_DEPS = {"c3d"}
"""Packages whose only dependency (numpy) FreeCAD ships: pip must not put a second numpy into
FreeCAD's extra-packages folder."""

FREECAD_PACKAGES_FOLDER = "AdditionalPythonPackages"
"""The folder of FreeCAD's user data that FreeCAD 0.20 and later put on sys.path at start-up
(when it exists) and where its Addon Manager pip-installs Python packages."""


def available(package: str) -> bool:
    """True when ``import package`` would find it (nothing is imported)."""
    try:
        return importlib.util.find_spec(package) is not None
    except (ImportError, ValueError):
        return False


def _base_python() -> str:
    """The Python interpreter FreeCAD's Python comes from (inside FreeCAD, sys.executable is
    FreeCAD itself): <base prefix>/bin/pythonX.Y when it exists, else pythonX.Y."""
    name = "python{}.{}".format(*sys.version_info[:2])
    for candidate in (os.path.join(sys.base_prefix, "bin", name),
                      os.path.join(sys.base_prefix, "python.exe")):
        if os.path.isfile(candidate):
            return candidate
    return name


def install_hint(package: str, freecad_user_dir: Optional[str] = None) -> str:
    """How to install ``package``: into FreeCAD's extra-packages folder when ``freecad_user_dir``
    (``FreeCAD.getUserAppDataDir()``) is given, else into the Python that runs ProgSurf."""
    if freecad_user_dir:
        target = os.path.join(freecad_user_dir, FREECAD_PACKAGES_FOLDER)
        no_deps = "--no-deps " if package in _NO_DEPS else ""
        return (f"install it into the folder FreeCAD adds to its Python path, then restart "
                f"FreeCAD: {_base_python()} -m pip install {no_deps}--target \"{target}\" "
                f"{package}")
    python = "python{}.{}".format(*sys.version_info[:2])
    return (f"install it into the Python that runs ProgSurf: {sys.executable or python} -m pip "
            f"install {package} (in a ProgSurf checkout, ./install.sh puts it into .venv)")


def missing_message(package: str, feature: str, freecad_user_dir: Optional[str] = None) -> str:
    """'<feature> needs <package>, which is not installed: <how to install it>'."""
    name = OPTIONAL_PACKAGES.get(package, f"the Python package '{package}'")
    return (f"{feature} needs {name}, which is not installed: "
            f"{install_hint(package, freecad_user_dir)}")


def require(package: str, feature: str, freecad_user_dir: Optional[str] = None):
    """Import and return the optional ``package``; raise MissingPackageError saying how to
    install it when it is missing. ``feature`` names what needs it, e.g. "reading C3D files"."""
    try:
        return importlib.import_module(package)
    except ImportError:
        raise MissingPackageError(missing_message(package, feature, freecad_user_dir),
                                  package, feature) from None


def for_freecad(error: MissingPackageError, freecad_user_dir: str) -> MissingPackageError:
    """The same error, its message saying how to install the package into FreeCAD's Python."""
    return MissingPackageError(missing_message(error.package, error.feature, freecad_user_dir),
                               error.package, error.feature)
