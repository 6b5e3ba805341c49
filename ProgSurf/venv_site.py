"""The checkout's .venv site-packages on sys.path, the one place that computes it.

PyPI-only packages (c3d) live in the checkout's .venv, made by install.sh on the same Python as
FreeCAD's. Init.py (FreeCAD start-up) loads this file by its path, so that starting FreeCAD
imports no ProgSurf package; the command line imports it. Standard library only.
"""
import os
import sys


def add_venv_site_packages(root: str) -> None:
    """Append <root>/.venv/lib/pythonX.Y/site-packages to sys.path when it exists (appended: it
    never shadows FreeCAD's own modules)."""
    version = "python{}.{}".format(*sys.version_info[:2])
    site = os.path.join(root, ".venv", "lib", version, "site-packages")
    if os.path.isdir(site) and site not in sys.path:
        sys.path.append(site)
