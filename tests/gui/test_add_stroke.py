"""A designer adds one interior stroke to a surface in the FreeCAD GUI (under Xvfb): the recompute
continues the last build (only the new stroke is added, faces away from it are reused), the shape is
one valid shell with the new patches, and one undo step takes it back exactly."""
from harness import require_gui, run_in_freecad_gui

SCRIPT = r'''
from PySide import QtGui
from ProgSurf.app import make

Gui.activateWorkbench("ProgSurfWorkbench")
doc = App.newDocument("AddStroke")
doc.UndoMode = 1
strokes = make.make_strokes_from_file({example!r}, doc=doc)
check(len(strokes) == 7, f"clean4 has 7 strokes, read {{len(strokes)}}")
surface = make.make_surface(boundary=strokes[:4], interior=strokes[4:-1])
doc.recompute()
before = (len(surface.Shape.Faces), surface.Shape.Area)
report("before", before)
doc.openTransaction("Add interior stroke(s)")
make.add_interior(surface, [strokes[-1]])
doc.commitTransaction()
process_events(0.5)
proxy = surface.Proxy
report("reused strokes", proxy.result.timings_s.get("reused strokes"))
report("faces reused/built", list(proxy.shell.reused["faces"]))
check(proxy.result.timings_s.get("reused strokes") == 6, "the 6 earlier strokes were not added again")
check(proxy.shell.reused["faces"][0] > 0 and proxy.shell.reused["faces"][1] > 0,
      "faces away from the new stroke are reused, the others built")
check(surface.Shape.ShapeType == "Shell" and surface.Shape.isValid(), "one valid shell")
check(len(surface.Shape.Faces) == before[0] + 2, f"{{len(surface.Shape.Faces)}} faces after the stroke")
check(strokes[-1].Status == "accepted", f"new stroke: {{strokes[-1].Status}} {{strokes[-1].Reason}}")
doc.undo()
doc.recompute()
check(list(surface.Interior) == strokes[4:-1], "undo removes the stroke")
check(len(surface.Shape.Faces) == before[0] and abs(surface.Shape.Area - before[1]) <= 1e-9 * before[1],
      f"undo brings the very same shape back: {{len(surface.Shape.Faces)}} faces, area {{surface.Shape.Area}}")
'''


def test_adding_a_stroke_in_the_gui_continues_the_surface():
    require_gui()
    from harness import ROOT

    run = run_in_freecad_gui(SCRIPT.format(example=str(ROOT / "examples" / "clean4.xyz")), timeout=300)
    assert run.ok, run.explain()
    assert run.checks >= 7, f"only {run.checks} checks ran: {run.values}"
