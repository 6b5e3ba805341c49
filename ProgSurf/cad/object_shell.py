"""One model of the whole object: every surface's faces sewn into one shell per connected part.

Each surface of core.objects is built by cad.shell.build_shell (its curves fitted once, its faces
exact Coons B-spline faces sewn into its own shell). Two surfaces on one network curve bound
themselves by the same polyline (core.objects), each fitting it within EDGE_FIT_FRACTION of the
fit tolerance as part of its own side, so their edges there lie within about the fit tolerance of
each other, not on one curve: OCC's sewing joins them at OBJECT_SEW_FRACTION of the fit tolerance
and gives the shared edge that tolerance (a gap this small is far below what any exchange or
meshing notices; sharing the very curve is left for later).

FreeCAD 0.20's Part.Shape.sewShape(tolerance) parses its tolerance and ignores it (it always sews at
1e-6 mm: TopoShapePy::sewShape calls TopoShape::sewShape() without it), so the sewing here runs
through the Surface workbench's Sewing feature, the one FreeCAD API that hands a tolerance to
BRepBuilderAPI_Sewing, in a temporary document.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from ..core.strokes import sketch_diagonal
from ..core.types import FloatArray, Tolerances
from ._occ import Part
from .g1 import OFFSET_FRACTION
from .object_g1 import across_angles, across_folds, across_maps, following, worst_side_deg
from .patch_faces import REFILL_ROWS
from .shared_edges import graph_curves, outer_edges
from .shell import build_shell

OBJECT_SEW_FRACTION = 4.0
"""Surfaces are sewn to one another at this multiple of the fit tolerance: each side is fitted
within half of it (cad.edges.EDGE_FIT_FRACTION) from the same polyline, so two fits of one curve
differ by at most the fit tolerance plus the chords' sag."""


@dataclass(frozen=True)
class ObjectShell:
    """The CAD model of an ObjectBuild.

    shape      : one Part.Shell (one connected part) or a Compound of shells (several parts, or
                 faces the sewing could not join: see `shells`)
    shells     : the sewn shells
    surfaces   : cad.shell.ShellResult per surface, in ObjectBuild.surfaces order
    face_owner : per face of `shape`, the index of the surface it belongs to
    tolerance  : the sewing tolerance between surfaces, mm
    timings_s  : "surfaces" (fitting every surface's faces), "folds across" (looking for them), "sew"
    across     : G1 with shared curves (cad.object_g1.across_angles): how many surface sides lie
                 along a curve another surface shares that is smooth ("smooth_sides") or drawn sharp
                 ("sharp_sides"; each shared piece counts once from each surface), the largest
                 angle between the two surfaces' normals along a smooth one and how many smooth
                 sides keep them within TANGENT_DEG, G1 ("angle_max_deg", "tangent_sides") and G0
                 ("g0_angle_max_deg", "g0_tangent_sides"); empty otherwise
    folds_across : with shared curves (loops), cad.object_g1.across_folds of the G0 faces: where two
                 surfaces part along a curve they share by more than FOLD_RISE_DEG beyond how the
                 strokes at its ends make them leave it (a crease, fin or tuck nobody drew)
    across_angle_max_deg : with shared curves, the largest angle between two surfaces' G0 normals
                 along a curve they share, between its ends (Across.angles at CHECK; creases drawn
                 sharp included); 0 without
    plain      : per surface, its ShellResult before `loosened` (G0 with shared curves): what a cache
                 of the surfaces keeps, so that each build decides its loose refills again with the
                 neighbours it has
    """

    shape: object
    shells: tuple
    surfaces: tuple
    face_owner: tuple
    tolerance: float
    timings_s: dict = field(default_factory=dict)
    across: dict = field(default_factory=dict)
    folds_across: tuple = ()
    across_angle_max_deg: float = 0.0
    plain: tuple = ()

    @property
    def closed(self) -> tuple:
        """isClosed() of each shell (a closed shell bounds a solid)."""
        return tuple(bool(s.isClosed()) for s in self.shells)


def _owner(shape, surfaces: list) -> tuple:
    """The surface each face of the sewn shape came from, found by a point of its surface."""
    from .sewing import probe_point

    probes, owners = [], []
    for k, res in enumerate(surfaces):
        for info in res.faces:
            probes.append(probe_point(info.face))
            owners.append(k)
    probes = np.array(probes).reshape(-1, 3)
    out = []
    for f in shape.Faces:
        p = np.array(probe_point(f))
        out.append(owners[int(np.argmin(np.linalg.norm(probes - p, axis=1)))])
    return tuple(out)


def with_vertices(face, points: list):
    """The face with its edges split at those of `points` (mm) that lie on an edge between its
    ends (within 1e-9 of the face's size): the same surface and boundary, more vertices
    (Part's general fuse of the face with those points)."""
    import FreeCAD

    size = max(face.BoundBox.DiagonalLength, 1e-300)
    near = 1e-9 * size + 1e-12
    split = []
    for p in points:
        v = Part.Vertex(FreeCAD.Vector(*map(float, p)))
        if any(v.distToShape(e)[0] <= near and min(v.distToShape(x)[0] for x in e.Vertexes) > near
               for e in face.Edges):
            split.append(v)
    if not split or any(e.Degenerated for e in face.Edges):
        # (a 3-sided face's collapsed side is a degenerated edge, which the fuse makes an
        # ordinary edge of no length, left free in the sewn shell: such faces are kept whole)
        return face
    fused, _ = face.generalFuse(split)
    out = fused.Faces
    return out[0] if len(out) == 1 and out[0].isValid() else face


def sew_at(faces: list, tolerance: float):
    """The faces sewn by BRepBuilderAPI_Sewing at `tolerance` mm (through Surface::Sewing, see
    the module docstring): a Shell, or a Compound of shells and faces."""
    import FreeCAD
    import Surface  # noqa: F401  (registers Surface::Sewing)

    doc = FreeCAD.newDocument("ProgSurfSewing", hidden=True)
    try:
        holder = doc.addObject("Part::Feature", "Faces")
        holder.Shape = Part.Compound(faces)
        sewing = doc.addObject("Surface::Sewing", "Sewing")
        sewing.ShapeList = [(holder, [f"Face{k + 1}" for k in range(len(faces))])]
        sewing.Tolerance = tolerance
        doc.recompute()
        shape = sewing.Shape.copy()
    finally:
        FreeCAD.closeDocument(doc.Name)
    if shape.isNull():
        shape = Part.Compound(faces)
    return shape


def loosened(built: list, results: list, given: list, reach: float) -> list:
    """The G0 surfaces (ShellResults) with each face that still folds refilled within its border
    alone, where its loop was seen from a tilted direction or untangled (cad.patch_faces.refilled_face
    loose), kept where that unfolds it and makes no crease with the other surfaces that the surface
    did not have (cad.object_g1.across_folds: no new (surfaces, curve) pair). Within the border
    alone, such a refill turns the face's tangent plane along its sides wherever the loop's map puts
    it: on the 82 unseen CASSIE sketches 14 more surfaces unfolded so, but 3 sketches traded a fold
    inside a surface for a crease along a curve it shares; checked so, 10 unfold and none creases
    (184 -> 174 folding, creases 52 either way). The creases are read among the surfaces whose boxes
    come within `reach` of the surface's (the sewing tolerance), before and after. given: per
    surface, its curves made once for the whole object (build_object_shell)."""
    networks = [r.network for r in results]
    boxes = None
    for k, res in enumerate(built):
        folding = _may_loosen(res)
        if not folding:
            continue
        trial = build_shell(results[k].network, results[k].tol, previous=res, given=given[k], loose=folding)
        # its loose faces (refilled or not) are kept with the surface as built: a later build that
        # decides again (an edit elsewhere: app.objects keeps `plain`) reads them there, not refills
        res.cache.faces.update({key: info for key, info in trial.cache.faces.items() if key[-1][1]})
        if not any(info.refilled and info.region_id in folding for info in trial.faces):
            continue
        if boxes is None:
            boxes = np.array([_box(r) for r in built])
        near = [int(i) for i in np.flatnonzero(np.all(boxes[:, 0] <= boxes[k, 1] + reach, axis=1)
                                               & np.all(boxes[:, 1] >= boxes[k, 0] - reach, axis=1))]

        def creases(shells: list) -> set:
            found = across_folds(shells, across_maps(shells, [networks[i] for i in near], reach))
            mine = near.index(k)
            return {(tuple(near[m] for m in f["surfaces"]), f["edge"]) for f in found if mine in f["surfaces"]}

        if creases([trial if i == k else built[i] for i in near]) <= creases([built[i] for i in near]):
            built = built[:k] + [trial] + built[k + 1:]
    return built


def _may_loosen(res) -> frozenset:
    """The region ids of a ShellResult's faces that `loosened` tries: each keeps its loop's map where
    it folds and no refill unfolded it (cad.patch_faces.FaceInfo.plane), reshaped."""
    return frozenset(info.region_id for info in res.faces if info.plane is not None and info.plane.reshaped)


def _box(res) -> FloatArray:
    """(2, 3): the lower and upper corners of the bounding box of a ShellResult's faces."""
    boxes = [info.face.BoundBox for info in res.faces]
    return np.array([[min(b.XMin for b in boxes), min(b.YMin for b in boxes), min(b.ZMin for b in boxes)],
                     [max(b.XMax for b in boxes), max(b.YMax for b in boxes), max(b.ZMax for b in boxes)]])


def build_object_shell(results: list, tol: Tolerances, continuity: str = "G0", built=None,
                       loops: tuple | None = None) -> ObjectShell:
    """Every surface's faces (cad.shell.build_shell of each BuildResult's network), sewn into
    one shell per connected part at OBJECT_SEW_FRACTION of the fit tolerance.
    built: per result, its ShellResult made earlier (with this continuity) to take as it is, or
    None to build it (app.objects keeps them for an edited sketch); not in G1 with loops, where the
    faces along a shared curve are made G1 with the other surface's (cad.object_g1).
    loops: ({graph edge id: (n, 3) points}, per result its cycle's ((graph edge id, reversed), ...),
    {(graph edge id, end): (3,) unit direction its curve leaves that node in} (core.node_tangents)):
    each graph edge is then fitted once and every surface's boundary edges are pieces of those
    curves (cad.shared_edges), so that surfaces on one curve share it exactly."""
    clock = time.perf_counter()
    across_g1 = continuity == "G1" and loops is not None
    # G1 across surfaces: a surface's faces depend on its neighbours', so every surface is built
    built = [None] * len(results) if across_g1 else list(built or [None] * len(results))
    given = [None] * len(results)
    if loops is not None:
        polylines, sides, tangents = loops
        todo = [k for k, b in enumerate(built) if b is None]
        used = {gid for k in todo for gid, _ in sides[k]}
        curves = graph_curves({gid: polylines[gid] for gid in used}, tol.fit_mm, tangents)
        for k in todo:
            given[k] = outer_edges(results[k].network, sides[k], curves)
        # a surface kept from an earlier build keeps the curves it was built on (loosened builds it
        # again on them: the very same curve objects, so its curves and faces are reused)
        given = [g if b is None else b.given for g, b in zip(given, built)]
    across, maps, g0 = {}, None, None
    if across_g1:
        # every surface in G0, the curves each shares with another found on those faces, then G1
        # on the same curves and G0 faces (previous=) with the other surfaces' normals there
        g0 = [build_shell(r.network, r.tol, given=g, refill_rows=REFILL_ROWS["G1"]) for r, g in zip(results, given)]
        maps = across_maps(g0, [r.network for r in results], OBJECT_SEW_FRACTION * tol.fit_mm)
        # (G1 moves a face by at most OFFSET_FRACTION of the diagonal of the whole sketch, as it
        # moves a single surface's by that of its own: issue 16's bound on the deviation from G0)
        limit = OFFSET_FRACTION * sketch_diagonal(np.vstack([np.asarray(p) for p in polylines.values()]))
        built = [build_shell(r.network, r.tol, continuity="G1", previous=b0, given=g, across=m, g1_limit_mm=limit)
                 for r, b0, g, m in zip(results, g0, given, maps)]
        # a side whose other surface's faces stayed G0 there aims at their normal: built again,
        # and kept where it then meets its neighbours more closely
        for k, m in enumerate(following(built, maps)):
            if m is not None:
                trial = build_shell(results[k].network, results[k].tol, continuity="G1", previous=built[k],
                                    given=given[k], across=m, g1_limit_mm=limit)
                swapped = built[:k] + [trial] + built[k + 1:]
                if worst_side_deg(swapped, maps, k) < worst_side_deg(built, maps, k):
                    built = swapped
        across = across_angles(built, maps)
        before = across_angles(g0, maps)
        across.update({"g0_angle_max_deg": before["angle_max_deg"], "g0_tangent_sides": before["tangent_sides"]})
    built = [b if b is not None else build_shell(r.network, r.tol, continuity=continuity, given=g)
             for r, b, g in zip(results, built, given)]
    plain = tuple(built)
    if loops is not None and continuity == "G0":
        built = loosened(built, results, given, OBJECT_SEW_FRACTION * tol.fit_mm)
    t_surfaces = time.perf_counter() - clock
    clock = time.perf_counter()
    folds_across, across_max = (), 0.0
    if loops is not None:
        # the surfaces' G0 faces along every curve two of them share: do they fold onto each other?
        if maps is None:
            g0 = built
            maps = across_maps(g0, [r.network for r in results], OBJECT_SEW_FRACTION * tol.fit_mm)
        folds_across = tuple(across_folds(g0, maps))
        angles = [a.angles for found in maps for a in found.values() if np.isfinite(a.angles).any()]
        across_max = float(max(np.nanmax(a) for a in angles)) if angles else 0.0
    t_folds = time.perf_counter() - clock
    clock = time.perf_counter()
    if loops is None:
        faces = [info.face for res in built for info in res.faces]
    else:
        # every face gets a vertex at each node of its surface's loop that lies inside one of its
        # edges (a node where two merged sides meet, or corners put elsewhere): the sewing joins
        # edge to edge, and a neighbour's vertex inside an edge left whole surfaces unsewn
        polylines, sides, _ = loops
        ends = [[np.asarray(polylines[gid][-1] if rev else polylines[gid][0], dtype=float) for gid, rev in loop]
                for loop in sides]
        faces = [with_vertices(info.face, ends[k]) for k, res in enumerate(built) for info in res.faces]
    tolerance = OBJECT_SEW_FRACTION * tol.fit_mm
    sewn = sew_at(faces, tolerance)
    shells = list(sewn.Shells)
    loose = [f for f in sewn.Faces if not any(f.isSame(g) for s in shells for g in s.Faces)]
    shells += [Part.Shell([f]) for f in loose]
    shape = shells[0] if len(shells) == 1 else Part.Compound(shells)
    timings = {"surfaces": t_surfaces, "folds across": t_folds, "sew": time.perf_counter() - clock}
    return ObjectShell(shape, tuple(shells), tuple(built), _owner(shape, built), tolerance, timings, across,
                       folds_across, across_max, plain)
