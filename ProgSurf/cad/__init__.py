"""ProgSurf.cad: the one adapter between the numeric core and OCC (FreeCAD's Part module).

Network polylines -> shared cubic B-spline edge curves (curves, on the numpy fit of core.curve_fit),
each network curve fitted once and cut into its edges (edges); regions -> exact Coons B-spline faces
(faces; per region, with their side pieces: patch_faces); faces -> one sewn shell (sewing); the three
steps, incremental through one ShellCache (shell); STEP/IGES export and fresh-process read-back
(export); G1 faces by flux correction (g1); what is derived from a face's surface, kept with the face
(surface_data); seam gaps, G1 defect, fit and stroke deviations (analysis); a matplotlib picture
(render).
Only this package imports FreeCAD/Part and converts numpy <-> FreeCAD.Vector.
"""
from .edges import fit_edges
from .patch_faces import FaceInfo, SidePiece
from .shell import ShellResult, build_shell
from .faces import coons_surface
from .export import export_iges, export_shape, export_step, read_back, skin_surface, summarize
from .analysis import (G1SeamStat, SeamStat, fit_deviation, g1_seam_stats, point_distances, seam_stats,
                       shape_point_distances, shell_seam_gaps)

__all__ = ["FaceInfo", "ShellResult", "SidePiece", "build_shell", "fit_edges", "coons_surface",
           "export_iges", "export_shape", "export_step", "read_back", "skin_surface", "summarize", "SeamStat",
           "fit_deviation", "point_distances", "seam_stats", "G1SeamStat", "g1_seam_stats", "shape_point_distances", "shell_seam_gaps"]
