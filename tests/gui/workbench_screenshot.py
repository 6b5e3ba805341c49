"""Take the README's picture of the ProgSurf workbench: FreeCAD under Xvfb, the workbench active,
a bundled example's strokes imported through the File > Import filter and a surface built from them.

Usage: .venv/bin/python tests/gui/workbench_screenshot.py [OUT.png] [EXAMPLE.xyz]
       (defaults: docs/workbench.png, examples/clean4.xyz). Exits non-zero when the run failed.
"""
import shutil
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from harness import ROOT, gui_unavailable_reason, run_in_freecad_gui  # noqa: E402

SCRIPT = r'''
from PySide import QtGui
from ProgSurf.app import make

Gui.activateWorkbench("ProgSurfWorkbench")
doc = App.newDocument("ProgSurf")
strokes = make.make_strokes_from_file({example!r}, doc=doc)
check(len(strokes) >= 4, f"{{len(strokes)}} strokes read from the example")
surface = make.make_surface(all_strokes=strokes)
doc.recompute()
check(surface.isValid() and not surface.Shape.isNull(), f"surface not built: {{surface.State}}")
report("faces", len(surface.Shape.Faces))

mdi = Gui.getMainWindow().findChild(QtGui.QMdiArea)
for sub in mdi.subWindowList():
    if "Start" in sub.windowTitle():
        sub.close()
view = Gui.ActiveDocument.ActiveView
view.viewIsometric()
view.fitAll()
Gui.Selection.clearSelection()
process_events(1.0)
grab_window("workbench")
'''


def main() -> int:
    out = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "docs" / "workbench.png"
    example = Path(sys.argv[2]) if len(sys.argv) > 2 else ROOT / "examples" / "clean4.xyz"
    reason = gui_unavailable_reason()
    if reason:
        print(f"workbench_screenshot: cannot run: {reason}", file=sys.stderr)
        return 2
    run = run_in_freecad_gui(SCRIPT.format(example=str(example.resolve())), timeout=300)
    if not run.ok:
        print(run.explain(), file=sys.stderr)
        return 1
    out.parent.mkdir(parents=True, exist_ok=True)
    shutil.copy(run.out_dir / "workbench.png", out)
    print(f"workbench_screenshot: {out} ({run.values})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
