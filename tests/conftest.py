"""pytest set-up shared by tests/core, tests/app and tests/gui.

FreeCAD's Python library is appended to sys.path and FreeCAD is imported first (before Part, and
before any test module); FreeCAD's own Mod folders are appended, as freecadcmd has them; then this
checkout is put at the front of sys.path so that `ProgSurf` is always the package under test, even
when FreeCAD's user Mod folder links another checkout.

Test modules are imported by basename (no __init__.py in tests/): keep file names unique across
tests/core, tests/app and tests/gui.
"""
import sys
from pathlib import Path

import pytest

FREECAD_LIB = "/usr/lib/freecad-python3/lib"
ROOT = Path(__file__).resolve().parent.parent
SHARED = ROOT.parent / "shared"

if FREECAD_LIB not in sys.path:
    sys.path.append(FREECAD_LIB)
import FreeCAD  # noqa: E402,F401  (must precede Part; runs the user Mod folders' Init.py)

# Imported from a plain Python, FreeCAD's home is /usr/lib/freecad-python3 and its own Mod
# folders (Draft, Sketcher, ...) are not on sys.path as they are under freecad/freecadcmd:
# append them (appended, so they shadow nothing; their Init.py files are not run).
for _folder in sorted((Path(FreeCAD.getResourceDir()) / "Mod").glob("*")) + [
        Path(FreeCAD.getResourceDir()) / "Ext"]:
    if _folder.is_dir() and str(_folder) not in sys.path:
        sys.path.append(str(_folder))

while str(ROOT) in sys.path:
    sys.path.remove(str(ROOT))
sys.path.insert(0, str(ROOT))


@pytest.fixture
def shared_data() -> Path:
    """../shared/data beside the checkout (real sketches); skips the test when absent."""
    data = SHARED / "data"
    if not data.is_dir():
        pytest.skip(f"{data} is absent: real sketches come with ../shared beside the checkout")
    return data


@pytest.fixture
def fresh_doc():
    """A new FreeCAD document, closed after the test."""
    doc = FreeCAD.newDocument("ProgSurfTest")
    yield doc
    if doc.Name in FreeCAD.listDocuments():
        FreeCAD.closeDocument(doc.Name)
