"""ProgSurf document layer: FeaturePython objects and the make_* scripting API.

Headless-safe: nothing here imports FreeCADGui or PySide at module level. When the GUI is up,
the make_* functions attach the view providers of ProgSurf.gui (as Draft's draftmake does).

  stroke_object   the Stroke feature: a polyline from points, a sketch chain or edges
  surface_object  the progressive Surface feature, recomputed through build
  network_object  the SurfaceNetwork feature: every surface of the stroke network (issue 18),
                  recomputed through objects, with each stroke's accounting
  proxy           what both features' proxies share: properties, restore, the saved state
  objects         build_object_and_measure: the whole-object orchestration (network + command line)
  build           build_and_measure: pipeline + cad shell + analysis, the one orchestration of
                  the document and the command line (cli.run_build); its report and face colours
  extract         sketches / edges / wires -> ordered 3D point lists
  make            the make_* scripting API (one call per command)
  importer        FreeCAD import module for stroke files (open / insert)
  params          the preference group holding default tolerances
"""
