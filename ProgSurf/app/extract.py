"""Sketches, edges and wires -> ordered 3D point lists (the strokes of Qin & Wright, section 2).

A designer's "stroke" is one connected chain of curve pieces. A Sketcher sketch may hold several
chains: each becomes one stroke. Chains are sampled by arc length and returned in 3D, in the
global frame (the sketch's global placement is applied).

Stroke points are checked here (shape, NaN/inf) and converted between numpy and FreeCAD.Vector
by the cad adapter's one conversion (ProgSurf.cad.curves.to_vectors / to_array).
"""
from __future__ import annotations

import math
from typing import Iterable, Sequence

import numpy as np

import FreeCAD  # noqa: F401  (FreeCAD before Part)
import Part

from ProgSurf.cad.curves import to_array, to_vectors
from ProgSurf.core.errors import InvalidStrokeError

JOIN_FRACTION = 1e-7
"""Two edge ends closer than this fraction of the edges' bounding-box diagonal (1e-5 mm for 100 mm
of edges), and at least OCC's confusion distance, are joined into one chain: ends a sketch joins
coincide to round-off, at any scale."""

OCC_CONFUSION_MM = 1e-7
"""OCC's Precision::Confusion: vertices closer than this are one vertex to OCC."""


def join_tolerance(edges: Sequence[Part.Edge]) -> float:
    """The distance under which two edge ends are joined (JOIN_FRACTION of the edges' size)."""
    if not edges:
        return OCC_CONFUSION_MM
    box = edges[0].BoundBox
    for e in edges[1:]:
        box.add(e.BoundBox)
    return max(JOIN_FRACTION * box.DiagonalLength, OCC_CONFUSION_MM)


def vectors_to_array(vectors: Iterable) -> np.ndarray:
    """FreeCAD vectors -> (n, 3) float array ((0, 3) when there are none)."""
    return to_array(vectors).reshape(-1, 3)


def array_to_vectors(points) -> list:
    """(n, 3) array-like -> list of FreeCAD.Vector; rejects NaN/inf with a clear message."""
    arr = np.asarray(points, dtype=float)
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise InvalidStrokeError(f"stroke points have shape {arr.shape}; expected (n, 3)")
    if not np.all(np.isfinite(arr)):
        raise InvalidStrokeError("stroke points contain NaN or inf; remove those rows")
    return to_vectors(arr)


def polyline_shape(vectors: Sequence) -> Part.Shape:
    """The stroke's Shape: a polyline wire through its points (empty shape if < 2 distinct)."""
    pts = [v for i, v in enumerate(vectors) if i == 0 or (v - vectors[i - 1]).Length > 1e-9]
    if len(pts) < 2:
        return Part.Shape()
    return Part.makePolygon(pts)


def _edge_key(edge: Part.Edge) -> tuple:
    return edge.Vertexes[0].Point, edge.Vertexes[-1].Point


def order_chains(edges: Sequence[Part.Edge]) -> list[list[tuple[int, bool]]]:
    """Group edges into connected chains and order each chain end to end.

    Returns a list of chains, each a list of (edge index, reversed). Chains are sorted by their
    lowest edge index, so a chain keeps its index while the sketch is only moved or reshaped.
    At a branching point the walk takes the lowest-numbered free edge; the rest form new chains.
    """
    ends = [_edge_key(e) for e in edges]
    used = [False] * len(edges)
    join = join_tolerance(edges)

    def touching(p, skip):
        hits = []
        for j, (a, b) in enumerate(ends):
            if used[j] or j == skip:
                continue
            if (a - p).Length <= join:
                hits.append((j, False))
            elif (b - p).Length <= join:
                hits.append((j, True))
        return hits

    def degree(p):
        return sum(((a - p).Length <= join) + ((b - p).Length <= join)
                   for j, (a, b) in enumerate(ends) if not used[j])

    chains = []
    for start in range(len(edges)):
        if used[start]:
            continue
        # walk backwards first to find the free end of this chain (or loop back to start)
        first, rev = start, False
        seen = {start}
        while True:
            head = ends[first][1] if rev else ends[first][0]
            prev = [h for h in touching(head, first) if h[0] not in seen]
            if not prev or degree(head) > 2:
                break
            j, j_rev_at_end = prev[0]
            # j touches our head with its end (flag True): j runs forwards into the head;
            # with its start (flag False): j must be run reversed.
            first, rev = j, not j_rev_at_end
            seen.add(j)
        chain = [(first, rev)]
        used[first] = True
        tail = ends[first][0] if rev else ends[first][1]
        while True:
            nxt = touching(tail, -1)
            if not nxt:
                break
            j, j_rev = nxt[0]
            used[j] = True
            chain.append((j, j_rev))
            tail = ends[j][0] if j_rev else ends[j][1]
        chains.append(chain)
    chains.sort(key=lambda c: min(i for i, _ in c))
    return chains


def sample_chain(edges: Sequence[Part.Edge], chain: Sequence[tuple[int, bool]],
                 samples: int) -> np.ndarray:
    """Sample a chain at about ``samples`` points spread by arc length; returns (n, 3)."""
    lengths = [max(edges[i].Length, 0.0) for i, _ in chain]
    total = sum(lengths) or 1.0
    out: list = []
    for (i, rev), length in zip(chain, lengths):
        count = max(2, int(math.ceil(samples * length / total)) + 1)
        pts = edges[i].discretize(Number=count)
        a, b = _edge_key(edges[i])
        # discretize follows the curve's parameter, not the edge orientation
        if (pts[0] - a).Length > (pts[0] - b).Length:
            pts = pts[::-1]
        if rev:
            pts = pts[::-1]
        out.extend(pts if not out else pts[1:])
    return vectors_to_array(out)


def sketch_geometry_edges(sketch) -> list[Part.Edge]:
    """The non-construction curve geometry of a sketch as edges in the global frame."""
    placement = sketch.getGlobalPlacement()
    edges = []
    for i, geo in enumerate(sketch.Geometry):
        if sketch.getConstruction(i) or isinstance(geo, Part.Point):
            continue
        edge = geo.toShape()
        edge.Placement = placement.multiply(edge.Placement)
        edges.append(edge)
    return edges


def sketch_chains(sketch, samples: int) -> list[np.ndarray]:
    """Qin & Wright's input strokes from a sketch: one (n, 3) array per connected chain."""
    edges = sketch_geometry_edges(sketch)
    return [sample_chain(edges, c, samples) for c in order_chains(edges)]


def object_edges(obj, subnames: Sequence[str] = ()) -> list[Part.Edge]:
    """Edges of ``obj`` (all, or the named sub-elements Edge<n>), in the global frame.

    Works for Part features, Draft Wire/BSpline/BezCurve and sketches alike.
    """
    if obj.isDerivedFrom("Sketcher::SketchObject") and not subnames:
        return sketch_geometry_edges(obj)
    names = [s for s in subnames if s]
    if not names:
        shape = Part.getShape(obj)
        return list(shape.Edges)
    edges = []
    for name in names:
        sub = Part.getShape(obj, name, needSubElement=True)
        edges.extend(sub.Edges)
    return edges


def edge_chains(obj, subnames: Sequence[str], samples: int) -> list[np.ndarray]:
    """Strokes from an object's edges: one (n, 3) array per connected chain."""
    edges = object_edges(obj, subnames)
    if not edges:
        raise InvalidStrokeError(f"object {obj.Name!r} {list(subnames)} has no edges; "
                                 "select a sketch, a wire or edges")
    return [sample_chain(edges, c, samples) for c in order_chains(edges)]
