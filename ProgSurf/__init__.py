"""ProgSurf: progressive freeform surfaces from rough, unorganised 3D sketch strokes.

Layers (see ../shared/STYLE.md):
  ProgSurf.core  numpy only: strokes, boundary, Coons patches, the pre-image plane network
  ProgSurf.io    stroke readers and writers (point lists, C3D), report JSON
  ProgSurf.cad   the one adapter to Part/OCC: B-spline edges and faces, shell, STEP/IGES, analysis
  ProgSurf.app   FeaturePython objects and the make_* scripting API (headless-safe)
  ProgSurf.gui   commands, view providers, task panels, preferences (FreeCADGui/PySide)
"""
__version__ = "0.1.0"
