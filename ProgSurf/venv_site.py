"""A developer checkout's extra paths (its .venv and tests/), the one place that computes them.

install.sh makes a checkout a developer install: a .venv on FreeCAD's Python for PyPI-only
packages (c3d), and a marker file in it. Only then does FreeCAD's start-up (Init.py) put that
venv's site-packages and the checkout's tests/ on sys.path; an addon installed by FreeCAD's
Addon Manager (no .venv, no marker) gets nothing of the sort. Init.py loads this file by its
path, so that starting FreeCAD imports no ProgSurf package; the command line imports it.
Standard library only.
"""
import os
import sys

INSTALL_MARKER = os.path.join(".venv", "progsurf-developer-install")
"""Written by install.sh, relative to the checkout: FreeCAD may use this checkout's .venv and tests/."""


def venv_site_packages(root: str) -> str:
    """<root>/.venv/lib/pythonX.Y/site-packages for the running Python (may not exist)."""
    version = "python{}.{}".format(*sys.version_info[:2])
    return os.path.join(root, ".venv", "lib", version, "site-packages")


def add_venv_site_packages(root: str) -> None:
    """Append the checkout's venv site-packages to sys.path when it exists (appended: it never
    shadows FreeCAD's own modules)."""
    site = venv_site_packages(root)
    if os.path.isdir(site) and site not in sys.path:
        sys.path.append(site)


def is_developer_install(root: str) -> bool:
    """True when install.sh set up this checkout (its marker is there)."""
    return os.path.isfile(os.path.join(root, INSTALL_MARKER))


def add_developer_paths(root: str) -> bool:
    """For a checkout set up by install.sh: append its venv site-packages and its tests/ to
    sys.path (tests/ last: it must never shadow a real module) and return True. Anything
    else (e.g. an Addon Manager install) is left alone: False."""
    if not is_developer_install(root):
        return False
    add_venv_site_packages(root)
    tests = os.path.join(root, "tests")
    if os.path.isdir(tests) and tests not in sys.path:
        sys.path.append(tests)
    return True
