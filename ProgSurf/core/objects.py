"""Whole-object mode: one progressive surface per cycle of the stroke network (issue 18, part 3).

    strokes -> filtered, faired once each                    (core.strokes, core.fairing)
            -> the stroke network                            (core.stroke_graph)
            -> the cycles that bound surfaces                (core.stroke_cycles)
            -> per cycle: its sides as the boundary, the dangling pieces inside it as interior
               strokes, through the progressive pipeline     (core.pipeline.build_network)

Every graph edge is cut from its faired stroke ONCE, and each surface along it takes that very
polyline as (part of) a boundary side: the two surfaces on a curve then bound themselves by the
same points, so their fitted edges agree within the fit tolerance and sew (cad.object_shell).
The pipeline is run on these polylines as they are (no second filtering or fairing, which would
treat a side differently in each of its two surfaces).

What became of every input stroke is recorded in StrokeRole: the surfaces it bounds, those it is
an interior stroke of, or why it is unused.
"""
from __future__ import annotations

import hashlib
import time
from dataclasses import dataclass, field, replace
from typing import Optional, Sequence

import numpy as np
import numpy.typing as npt

from .boundary import BoundaryLoop, best_fit_plane, boundary_from_sides, stroke_end_pairs
from .continuity import KINK_WINDOW, turning_angles, unit
from .coons import f1
from .errors import ProgSurfError
from .fairing import fair_stroke, stroke_tolerance
from .loop_corners import choose_sides
from .loop_split import MIN_SIDES, best_division
from .node_tangents import node_tangents
from .open_corners import ease_over, open_corners
from .pipeline import BuildResult, build_network, resolve_tolerances
from .stroke_cycles import Cycle, CycleChoice, find_cycles, vector_area
from .stroke_graph import StrokeGraph, build_stroke_graph
from .strokes import chord_length, cumulative_length, filter_stroke, point_at_length, round_points, validate_stroke
from .twice_drawn import twice_drawn
from .types import FloatArray, Tolerances

EASE_REACHES = (0.1, 0.2)
"""An edge whose first segment leaves its node more than EASE_DEG off the chord to its point this
share of its length along (the shorter reach first: a curl or hook at its end, a VR stroke
overshooting its corner, a noisy stroke's end faired into a loop; a hook longer than a tenth
leaves the first chord aligned with it, the second not) ...

The side of a Coons patch with Hermite blends has, as its cross-boundary derivative all along it,
the blend of its two neighbouring sides' end tangents: a curl of a millimetre at a side's end
turned the patch over along a whole strip of each neighbouring side (CASSIE 02-0-2, the noisy
TiGL fuselage, where one side of 1.8 m hooked back over its first 200 mm)."""

EASE_DEG = 30.0
"""... gets that share replaced by a cubic from its node along that chord to the point there, in
the edge's own direction at that point (a circular arc's end leaves the chord by half its turn
over that share: 18 deg for a half circle over a fifth of it)."""

INSIDE_FRACTION = 0.6
"""A dangling piece is an interior stroke of the surface whose loop holds at least this fraction
of its points (in the loop's best-fit plane) ..."""

INSIDE_HEIGHT = 0.25
"""... and whose points lie within this fraction of the loop's diagonal of that plane."""

SURFACE_MODES = ("auto", "all", "one")
"""--surfaces: every surface of the network, today's single surface, or the one the sketch shows."""


@dataclass(frozen=True)
class StrokeRole:
    """What became of one input stroke.

    boundary_of : indices (in ObjectBuild.surfaces) of the surfaces it bounds
    interior_to : indices of the surfaces it was added to as an interior stroke
    reason      : for a stroke that is neither, why; else a short note (merged, hook removed)
    """

    index: int
    boundary_of: tuple = ()
    interior_to: tuple = ()
    reason: str = ""

    @property
    def used(self) -> bool:
        return bool(self.boundary_of or self.interior_to)

    def describe(self) -> str:
        parts = []
        if self.boundary_of:
            parts.append("boundary of surface(s) " + ", ".join(map(str, self.boundary_of)))
        if self.interior_to:
            parts.append("interior to surface(s) " + ", ".join(map(str, self.interior_to)))
        if not parts:
            parts.append("unused: " + (self.reason or "no reason recorded"))
        elif self.reason:
            parts.append(self.reason)
        return "; ".join(parts)


@dataclass(frozen=True)
class ObjectSurface:
    """One surface of the object.

    cycle    : the network cycle that bounds it
    result   : the pipeline's BuildResult (network, records: the sides first, then the interior
               pieces), built on the cycle's side polylines
    sides    : the graph edge ids of its sides, in loop order
    interior : the graph edge ids added as interior strokes (dangling pieces inside it)
    part     : the connected part of the network it belongs to
    key      : digest of everything `result` depends on (surface_key): its side and interior
               polylines and the tolerances it was built with
    reused   : True when `result` was taken from a BuildCache (an earlier build had the same key)
    curves_key : digest of the directions its side curves must have at the nodes a stroke passes
               through (ObjectBuild.tangents): its faces depend on them, its core result does not
    """

    cycle: Cycle
    result: BuildResult
    sides: tuple
    interior: tuple
    part: int
    key: bytes = b""
    reused: bool = False
    curves_key: bytes = b""


@dataclass(frozen=True)
class ObjectBuild:
    """The outcome of build_object.

    graph    : the stroke network           choice : its cycles (chosen and dropped)
    surfaces : ObjectSurface per built cycle
    failed   : [(Cycle, reason)] cycles the pipeline could not make a surface of
    roles    : StrokeRole per input stroke, in input order
    tol      : the tolerances used (automatic values resolved from the whole sketch)
    timings_s: seconds: "graph", "cycles", "surfaces"
    polylines: graph edge id -> its faired points (n, 3) (edge_polylines), the surfaces' sides;
               and the curves drawn across divided loops (ids from len(graph.edges) on)
    tangents : {(graph edge id, end 0/1): (3,) unit direction} where a stroke runs smoothly through
               a node (core.node_tangents): the graph edges' curves leave their nodes along these
    divisions: per loop divided in two (core.loop_split), (the id of the curve across it, the
               input strokes of its sides, its patch's turn, the worse part's; deg)
    opened   : per corner opened (core.open_corners), the graph edge ids of its two sides
    """

    graph: StrokeGraph
    choice: CycleChoice
    surfaces: tuple
    failed: tuple
    roles: tuple
    tol: Tolerances
    timings_s: dict = field(default_factory=dict)
    polylines: dict = field(default_factory=dict)
    tangents: dict = field(default_factory=dict)
    divisions: tuple = ()
    opened: tuple = ()

    def surfaces_along(self, edge_id: int) -> list:
        """Indices (into surfaces) of the surfaces a graph edge or a curve across (divisions) bounds."""
        return [k for k, surf in enumerate(self.surfaces) if edge_id in surf.sides]

    def surfaces_at(self, corner: tuple) -> list:
        """Indices (into surfaces) of the surfaces both edges of a corner (opened) bound."""
        return [k for k, surf in enumerate(self.surfaces) if all(e in surf.sides for e in corner)]

    @property
    def rebuilt(self) -> tuple:
        """Indices (into surfaces) of the surfaces this build made; the others came from a cache."""
        return tuple(k for k, s in enumerate(self.surfaces) if not s.reused)


class BuildCache:
    """What earlier whole-object builds made, for the next build of an edited sketch to reuse
    (issue 18: adding or moving one stroke rebuilds only the surfaces it touches).

    Every entry is keyed by a digest of the exact input it was made from (the points' bytes and the
    tolerances), never by a name or a position in a list: a surface whose side and interior
    polylines and tolerances are unchanged is taken as it was; any change to them, or to an option
    that reaches them (the tolerances, resolved from the whole sketch), makes a new key and so a
    new build. A key is a function of the whole input, so a reused result is the result a build
    from scratch makes.

    Entries are grouped by kind: "faired" (a filtered stroke -> its faired points), "surface" (a
    surface key -> its BuildResult, or the reason it failed); callers above the core add their own
    kinds (app.objects: the CAD faces of a surface). Each build keeps the entries it used or made,
    and those of the GENERATIONS builds before it (`start` moves them back one generation), so an
    undo (the strokes of two builds ago) finds its surfaces too, while the cache does not grow with
    every edit."""

    GENERATIONS = 2

    def __init__(self) -> None:
        self.entries: dict = {}
        self.older: list = []

    def start(self) -> None:
        """Begin a new build: this build's entries become the newest older generation."""
        if self.entries:
            self.older = [self.entries] + self.older[:self.GENERATIONS - 1]
            self.entries = {}

    def lookup(self, kind: str, key):
        """The entry of `kind` and `key` from this build or the ones before (then moved to this
        build's generation), or None."""
        k = (kind, key)
        if k in self.entries:
            return self.entries[k]
        for generation in self.older:
            if k in generation:
                self.entries[k] = generation[k]
                return self.entries[k]
        return None

    def store(self, kind: str, key, value) -> None:
        self.entries[(kind, key)] = value


def content_key(*parts) -> bytes:
    """A digest of arrays (their shape and float64 bytes) and strings (their text), in order."""
    h = hashlib.blake2b(digest_size=20)
    for p in parts:
        if isinstance(p, str):
            h.update(b"s" + p.encode())
        else:
            a = np.ascontiguousarray(p, dtype=float)
            h.update(b"a" + repr(a.shape).encode() + a.tobytes())
        h.update(b"|")
    return h.digest()


def surface_key(sides: list, interior: list, tol: Tolerances) -> bytes:
    """What one surface's BuildResult depends on: its sides' and interior pieces' polylines (in
    order) and the tolerances its pipeline runs with."""
    return content_key(repr(tol), f"{len(sides)} sides", *sides, f"{len(interior)} interior", *interior)


def _faired_strokes(filtered: list, tol: Tolerances, cache: Optional[BuildCache] = None) -> tuple[list, list]:
    """Each filtered stroke faired once (core.fairing), as the pipeline fairs an interior stroke:
    (faired points per stroke, and per stroke the index in its faired points of each filtered
    point: where the fit put that point, which maps the graph's arc lengths onto the faired
    stroke, _stroke_arcs)."""
    out, origins = [], []
    params = repr((tol.fit_mm, tol.fair_mm, tol.snap_mm, tol.sag_mm))
    for pts in filtered:
        key = content_key(params, pts) if cache is not None else None
        done = cache.lookup("faired", key) if cache is not None else None
        if done is None:
            pts = round_points(pts, tol.fit_mm)
            ftol = stroke_tolerance(pts, tol.fair_mm, tol.snap_mm)
            at: list = []
            done = ((fair_stroke(pts, ftol, tol.sag_mm, original_at=at)[0], np.asarray(at, dtype=int))
                    if len(pts) >= 2 else (pts, np.arange(len(pts))))
        if cache is not None:
            cache.store("faired", key, done)
        out.append(done[0])
        origins.append(done[1])
    return out, origins


def edge_polylines(graph: StrokeGraph, faired: list, origins: Optional[list] = None,
                   arcs: Optional[dict] = None) -> dict:
    """edge id -> its points cut from the faired stroke (the graph's arc lengths carried onto it,
    _stroke_arcs), ends replaced by its nodes' points on the faired strokes (faired_nodes) exactly,
    and no stroke point left within half the stroke's median chord of them. origins: per stroke,
    the index in its faired points of each filtered point (_faired_strokes); None when each faired
    stroke has the filtered stroke's points, moved. arcs: _stroke_arcs, when the caller has them."""
    arcs = _stroke_arcs(graph, faired, origins) if arcs is None else arcs
    nodes = faired_nodes(graph, faired, origins, arcs)
    out = {}
    for e in graph.edges:
        src = faired[e.stroke]
        to_faired, cum = arcs[e.stroke]
        a, b = float(to_faired(e.s0)), float(to_faired(e.s1))
        keep = (cum > a) & (cum < b)
        inner = src[keep]
        if len(inner) and b > a:
            # the faired stroke passes its nodes at some distance (each node is the mean of the
            # strokes there): that offset is spread along the edge, the whole of it at its node
            # and none at the other end, with no slope at either, so that the edge leaves its node
            # in its stroke's own direction instead of jumping to it in one segment (a hook that
            # turned the Coons patches of noisy loops over at their corners)
            fade = f1((cum[keep] - a) / (b - a))[:, None]
            inner = (inner + fade * (nodes[e.node0] - point_at_length(src, a, cum))
                     + (1.0 - fade) * (nodes[e.node1] - point_at_length(src, b, cum)))
        if len(inner) and len(cum) > 1:
            # no stroke point within half a chord of a node: the node lies beside the stroke (the
            # mean of the strokes crossing there), and a stroke point just past it made a first
            # chord of 0.002-0.02 mm at about 90 deg, a lip along the whole edge of the faces
            # (a crease of 70-90 deg on the edge itself where the strokes are smooth)
            h = 0.5 * float(np.median(np.diff(cum)))
            inner = inner[(np.linalg.norm(inner - nodes[e.node0], axis=1) > h)
                          & (np.linalg.norm(inner - nodes[e.node1], axis=1) > h)]
        pts = np.vstack([nodes[e.node0], inner, nodes[e.node1]])
        if len(pts) == 2:
            pts = point_at_length(pts, np.linspace(0.0, chord_length(pts), 3))
        out[e.id] = _eased(_eased(pts)[::-1])[::-1]
    return out


def _eased(pts: FloatArray) -> FloatArray:
    """An edge's polyline with a curl or hook at its start eased away (EASE_REACHES, EASE_DEG): the
    points before that share of its length replaced by a cubic Hermite arc from its start (tangent
    along the chord) to the point there (the polyline's tangent there), as many points as they were
    (at least 4). The start point itself, the node, is kept exactly."""
    cum = cumulative_length(pts)
    total = float(cum[-1])
    if len(pts) < 3 or not total > 0:
        return pts
    first = unit(pts[1] - pts[0])
    if not first.any():
        return pts
    for share in EASE_REACHES:
        reach = share * total
        at = point_at_length(pts, reach, cum)
        chord = unit(at - pts[0])
        if chord.any() and np.degrees(np.arccos(min(max(float(first @ chord), -1.0), 1.0))) > EASE_DEG:
            break
    else:
        return pts
    return ease_over(pts, share)


def _stroke_arcs(graph: StrokeGraph, faired: list, origins: Optional[list] = None) -> dict:
    """stroke index -> (a map of arc length along the filtered stroke, the graph's s0/s1, to arc
    length along the faired one; the faired stroke's cumulative_length), once per stroke that has
    an edge.

    The map runs through the filtered points' own places on the faired stroke (origins: where the
    fit put each of them), piecewise linear between them. Scaling the arc length by the two
    lengths' ratio instead put the edges' ends hundreds of mm from their nodes on a noisy stroke
    whose zigzag is denser in some parts than others (TiGL fuselage1 noisy: the filtered stroke
    up to twice the faired one's length, unevenly), and the surfaces' sides then ran past their
    corners and back: most of its loops' Coons patches turned over."""
    out = {}
    for i in {e.stroke for e in graph.edges}:
        src = faired[i]
        cum = cumulative_length(src)
        filtered_cum = cumulative_length(graph.strokes[i])
        at = np.arange(len(src)) if origins is None else np.asarray(origins[i], dtype=int)
        if len(at) != len(filtered_cum):
            raise ValueError(f"stroke {i}: {len(at)} faired places for {len(filtered_cum)} filtered points")
        knots = np.maximum.accumulate(cum[at])
        out[i] = (lambda s, x=filtered_cum, y=knots: np.interp(s, x, y), cum)
    return out


def faired_nodes(graph: StrokeGraph, faired: list, origins: Optional[list] = None,
                 arcs: Optional[dict] = None) -> dict:
    """node id -> (3,) its point on the faired strokes: the mean of the faired strokes' points at the
    places its edges end (each stroke and arc length once; arc lengths carried over as in
    edge_polylines), as the graph's node is the mean of the filtered strokes' points there.

    Why: fairing moves a stroke by up to the fairing tolerance, so an edge cut to the filtered
    node jumped that far in its first segment; on a piece a few times as long (a small profile
    between two crossings: 26 mm with jumps of up to 2.9 mm on the TiGL helibody's boom) that was a
    kink its curve fit could not follow. Two strokes crossing now meet at the middle of their
    faired points, each edge's jump half their separation there. arcs: _stroke_arcs, when the
    caller has them."""
    arcs = _stroke_arcs(graph, faired, origins) if arcs is None else arcs
    on: dict = {}
    for e in graph.edges:
        src = faired[e.stroke]
        to_faired, cum = arcs[e.stroke]
        for node, s in ((e.node0, e.s0), (e.node1, e.s1)):
            on.setdefault(node, {}).setdefault((e.stroke, s), point_at_length(src, float(to_faired(s)), cum))
    return {node: np.mean(list(points.values()), axis=0) for node, points in on.items()}


KINK_SPLIT_DEG = 45.0
"""A loop of fewer than four sides whose side turns by more than this (continuity.turning_angles,
over KINK_WINDOW of the side each way) is cut there, at its sharpest such turn, before any side is
cut at its middle: a designer draws two sides of a triangle as one stroke bent at their corner,
and a cut at the middle of a side puts that corner elsewhere and squeezes the patch round the
bend (CASSIE 02-0-2 surface 27 and 10-2-1 surface 46, 3-sided loops whose patches turned over 118
and 128 deg, lie flat with their bends as corners). Only sides no other surface shares, unless
the loop has fewer than three: cutting shared sides at their bends made creases between surfaces
along them (the noisy TiGL fuselage and helibody, 72 and 94 deg) while it took the 12 real
sketches' folding surfaces to 51 (54 with own sides only, 56 before)."""

KINK_END = 0.1
"""... a turn within this share of the side's length from one of its ends is not a corner of it:
there the window is short and a stroke's hook reads as a turn."""


def _sharpest_kink(points: FloatArray, window_mm: float = 0.0) -> tuple[float, int]:
    """(turn in deg, index) of a side's sharpest turn at least KINK_END of its length from its ends
    ((0, -1) when it has no point there), read over KINK_WINDOW of its length each way or
    window_mm, the longer: a turn shorter than the stroke filter's distance is the hand's jitter
    (the noisy TiGL fuselage: a piece whose noise read as an 81 deg turn over 4 % of it)."""
    pts = np.asarray(points, dtype=float)
    if len(pts) < 5:
        return 0.0, -1
    cum = cumulative_length(pts)
    if not cum[-1] > 0:
        return 0.0, -1
    inside = (cum >= KINK_END * cum[-1]) & (cum <= (1.0 - KINK_END) * cum[-1])
    inside[[0, -1]] = False
    if not inside.any():
        return 0.0, -1
    turns = np.where(inside, turning_angles(pts, max(KINK_WINDOW, window_mm / cum[-1])), -1.0)
    k = int(np.argmax(turns))
    return float(turns[k]), k


def _split_few_sides(sides: list, flags: list, window_mm: float = 0.0) -> tuple[list, list]:
    """A loop of fewer than four sides (a closed stroke, two strokes between the same two nodes,
    three strokes) is cut until it has four: at the sharpest turn of a side sharper than
    KINK_SPLIT_DEG (_sharpest_kink, over at least window_mm), else its longest side at its middle.
    flags: one per side; returns (sides, flags), each half keeping its side's flag."""
    sides, flags = list(sides), list(flags)
    while len(sides) < 4:
        kinks = [_sharpest_kink(side, window_mm) if own or len(sides) < 3 else (0.0, -1)
                 for side, own in zip(sides, flags)]
        k = max(range(len(sides)), key=lambda i: kinks[i][0])
        pts = sides[k]
        if kinks[k][0] > KINK_SPLIT_DEG:
            at = kinks[k][1]
            a, b = pts[:at + 1], pts[at:]
        else:
            k = max(range(len(sides)), key=lambda i: chord_length(sides[i]))
            pts = sides[k]
            cum = cumulative_length(pts)
            half = 0.5 * cum[-1]
            mid = point_at_length(pts, half)
            a = np.vstack([pts[cum < half], mid])
            b = np.vstack([mid, pts[cum > half]])
        if len(a) < 2 or len(b) < 2:
            break
        sides[k:k + 1] = [a, b]
        flags[k:k + 1] = [flags[k], flags[k]]
    return sides, flags


def _shaped_loop(sides: list, inner: list, own: list, chosen=None) -> tuple[list, BoundaryLoop]:
    """A cycle's sides and its BoundaryLoop: the paper's corners (boundary_from_sides), or where
    their base patch would fold, the corners loop_corners.choose_sides finds (a note says so).
    chosen: (what choose_sides gave,) for these sides, own and no inner strokes, if known."""
    ends = stroke_end_pairs(inner, range(len(inner))) if inner else None
    chosen = chosen[0] if chosen is not None else choose_sides(sides, ends, own)
    if chosen is None:
        return sides, boundary_from_sides(sides, list(range(len(sides))), inner)
    shaped, apex, before, after = chosen
    loop = boundary_from_sides(shaped, list(range(len(shaped))), inner, apex=1 if apex == 1 else None)
    note = (f"corners moved: with the merged sides' corners its base patch turns {before:.0f} deg inside "
            f"it (a fold), with these {len(shaped)} corners {after:.0f} deg")
    return shaped, replace(loop, notes=tuple(loop.notes) + (note,))


class _Loop:
    """A chosen cycle's loop in its best-fit plane, found once for every piece tested against it.
    loop : (n, 3) its points in order (each side without its last point); kept: the plane, the
    loop's polygon there, its diagonal (`diag`, at least 1e-300, and `size`)."""

    def __init__(self, loop: FloatArray) -> None:
        self.plane = best_fit_plane(loop)
        poly = self.plane.project(loop)
        self.x, self.y = poly[:, 0], poly[:, 1]
        self.x2, self.y2 = np.roll(self.x, -1), np.roll(self.y, -1)
        dy = self.y2 - self.y
        self.dy = np.where(dy == 0, 1e-300, dy)
        self.diag = max(float(np.linalg.norm(loop.max(axis=0) - loop.min(axis=0))), 1e-300)
        self.size = float(np.linalg.norm(loop.max(axis=0) - loop.min(axis=0)))

    def height(self, points: FloatArray) -> float:
        """Largest height of the points over the plane as a fraction of the loop's diagonal."""
        return float(np.abs((points - self.plane.origin) @ self.plane.normal).max() / self.diag)

    def inside(self, points: FloatArray) -> float:
        """Fraction of the points inside the loop in its plane (even-odd rule)."""
        q = self.plane.project(points)
        x, y = self.x, self.y
        crosses = ((y[None] > q[:, 1:2]) != (self.y2[None] > q[:, 1:2])) & (
            q[:, 0:1] < (self.x2 - x)[None] * (q[:, 1:2] - y[None]) / self.dy[None] + x[None])
        return float((crosses.sum(axis=1) % 2 == 1).mean())


def _assign_interior(graph: StrokeGraph, choice: CycleChoice, polylines: dict, merged: dict) -> dict:
    """cycle index -> [edge ids]: each edge that bounds no chosen cycle goes to the cycle whose
    loop holds it (INSIDE_FRACTION, INSIDE_HEIGHT); the smallest such loop when several do. Edges
    merged into another (merged: core.twice_drawn) lie on a boundary already and go to none; nor
    do bridges (CycleChoice.bridges), which join a group of curves to the loop round them: laid
    in as an interior stroke, a bridge's end at that group would be extended across the surface
    past it (on the 82 CASSIE sketches not in ../shared, 451 surfaces of 2803 folded with bridges
    inside, 409 of 2839 without).
    (Each loop's plane is fitted once; a piece too far from a loop's plane is not tested for
    being inside it.)"""
    bounding = {e for c in choice.cycles for e in c.edge_ids}
    loops = [_Loop(np.vstack([p[:-1] for p in c.polylines(graph)])) for c in choice.cycles]
    out: dict = {}
    for e in graph.edges:
        if e.id in bounding or e.id in merged or e.id in choice.bridges:
            continue
        best = None
        for k, loop in enumerate(loops):
            if best is not None and loop.size >= loops[best].size:
                continue
            if loop.height(polylines[e.id]) <= INSIDE_HEIGHT and loop.inside(polylines[e.id]) >= INSIDE_FRACTION:
                best = k
        if best is not None:
            out.setdefault(best, []).append(e.id)
    return out


FACING = 0.7
"""--surfaces auto: a one-part sheet without one outer border (choose_mode) whose loops' vector areas
add up to less than this share of their sizes (the loops face different ways: a closed shell, a
tube, a body that wraps round) is built as every surface. On the sketchgen families of seed bases
45000 and 53000 (360 single surfaces, noisy and clean) the share was 0.84 or more, and on the 864
sketches of the project's own generator of seed bases 0-700000 (benchmarks.sketches, noisy and
clean) 0.83 or more;
on the real objects of ../shared/data that are one part, 0.62 or less (vintage_car 0.62, the
lamp 04-1-1 0.49, the TiGL tubes 0.005-0.06)."""


def facing_share(graph: StrokeGraph, choice: CycleChoice) -> float:
    """|sum of the chosen loops' vector areas| / sum of their sizes: 1 when every loop faces the
    same way (one sheet that could be one surface over a plane), near 0 for a closed shell. The
    loops of a manifold choice run the same way round their shared curves, so their vector areas
    are oriented alike."""
    if not choice.cycles:
        return 1.0
    areas = np.array([vector_area(c.loop_points(graph)) for c in choice.cycles])
    size = float(np.linalg.norm(areas, axis=1).sum())
    return float(np.linalg.norm(areas.sum(axis=0)) / size) if size > 0 else 1.0


def choose_mode(choice: CycleChoice, graph: Optional[StrokeGraph] = None) -> str:
    """The surfaces the sketch shows, for --surfaces auto: "one" for no loop at all, or one
    connected sheet whose outer border is one loop round the others (its outer face, no rims of
    a tube), or whose loops all face one way (facing_share at least FACING, which a sheet whose
    border did not close, such as a 5-sided boundary drawn with an open corner, still has); "all"
    otherwise (several parts, a closed shell, a tube, loops facing every way). A sheet that wraps
    round, like a car's roof and sides, has one outer border too: the single surface is then
    refused for want of one boundary loop, and the command line builds every surface instead
    (object_cli.fallback_object). Without the graph the loops' facing is not known."""
    parts = {c.sides[0][0] for c in choice.cycles}
    parts = {p for p, edges in enumerate(choice.parts) if edges & parts}
    if len(choice.cycles) <= 1 or len(parts) > 1:
        return "one" if len(choice.cycles) <= 1 else "all"
    outer = [c for c, reason in choice.dropped if reason.startswith("outer face")]
    rims = [c for c, reason in choice.dropped if reason.startswith("spans no surface")]
    if len(outer) == 1 and not rims:
        return "one"
    return "one" if graph is not None and facing_share(graph, choice) >= FACING else "all"


def build_object(strokes: Sequence[npt.ArrayLike], tol: Tolerances = Tolerances(),
                 network: Optional[tuple] = None, cache: Optional[BuildCache] = None) -> ObjectBuild:
    """Every surface the stroke network bounds, each through the progressive pipeline.

    strokes : (n_i, 3) point arrays in mm, in drawing order
    network : (StrokeGraph, CycleChoice, tol) made by `stroke_network` for these strokes, to
              reuse; None = make them here
    cache   : a BuildCache of earlier builds (of this or another sketch): a surface whose inputs
              are unchanged is taken from it (ObjectSurface.reused), and a stroke faired before is
              not faired again; this build's results are stored in it for the next
    A cycle the pipeline cannot make a surface of is recorded in `failed` with the reason; a
    sketch with no cycle at all raises a ProgSurfError naming why."""
    timings: dict = {}
    clock = time.perf_counter()
    if cache is not None:
        cache.start()
    graph, choice, tol = network if network is not None else stroke_network(strokes, tol)
    faired, origins = _faired_strokes(list(graph.strokes), tol, cache)
    arcs = _stroke_arcs(graph, faired, origins)
    polylines = edge_polylines(graph, faired, origins, arcs)
    tangents = node_tangents(graph, faired, arcs, polylines)
    choice, merged = twice_drawn(graph, choice, polylines)
    polylines, opened = open_corners(choice, polylines, {e.id: e.stroke for e in graph.edges}, tangents)
    timings["graph"] = time.perf_counter() - clock
    if not choice.cycles:
        raise ProgSurfError(
            f"the {len(graph.strokes)} strokes make a network of {len(graph.nodes)} nodes and "
            f"{len(graph.edges)} edges but no closed loop of curves: no surface is bounded; draw "
            f"strokes that cross or meet (within {graph.delta:.3g} mm) around each surface")
    clock = time.perf_counter()
    interior = _assign_interior(graph, choice, polylines, merged)
    part_of = {e: p for p, edges in enumerate(choice.parts) for e in edges}
    # each surface's polylines as they are: no second filtering or fairing (module docstring)
    inner_tol = replace(tol, filter_mm=0.0, fair_mm=0.0)
    surfaces, failed = [], []
    uses: dict = {}
    for cycle in choice.cycles:
        for e, _ in cycle.sides:
            uses[e] = uses.get(e, 0) + 1
    polylines = dict(polylines)
    loops, divisions, screened = _divided(graph, [(c, interior.get(k, [])) for k, c in enumerate(choice.cycles)],
                                          polylines, uses, cache)
    for n, (cycle, inside) in enumerate(loops):
        # a side no other surface shares may get a corner in its middle (loop_corners)
        sides, own = _split_few_sides(cycle.polylines_from(polylines), [uses[e] == 1 for e, _ in cycle.sides],
                                      tol.filter_mm or 0.0)
        inner = [polylines[e] for e in inside]
        key = (surface_key(sides, inner, inner_tol), tuple(own))
        done = cache.lookup("surface", key) if cache is not None else None
        reused = done is not None
        if done is None:
            try:
                shaped, loop = _shaped_loop(sides, inner, own, screened.get(n))
                done = build_network(shaped + inner, boundary=list(range(len(shaped))), tol=inner_tol, loop=loop)
            except ProgSurfError as exc:
                done = str(exc)
        if cache is not None:
            cache.store("surface", key, done)
        if isinstance(done, str):
            failed.append((cycle, done))
            continue
        surfaces.append(ObjectSurface(cycle, done, tuple(e for e, _ in cycle.sides), tuple(inside),
                                      part_of[next(e for e, _ in cycle.sides if e in part_of)], key, reused,
                                      _curves_key(cycle, tangents)))
    timings["surfaces"] = time.perf_counter() - clock
    return ObjectBuild(graph, choice, tuple(surfaces), tuple(failed), _roles(graph, choice, surfaces, failed, merged),
                       tol, timings, polylines, tangents, tuple(divisions), tuple(opened))


def _divided(graph: StrokeGraph, loops: list, polylines: dict, uses: dict,
             cache: Optional[BuildCache] = None) -> tuple[list, list, dict]:
    """The (cycle, interior edge ids) to build: each loop of loop_split.MIN_SIDES or more sides,
    with no stroke inside it, whose patch folds whatever its corners, divided in two by a curve
    across it where neither part folds (loop_split.best_division). The curves are added to
    polylines (ids from len(graph.edges) on) and counted in uses (twice: each bounds both
    parts); returns (the loops, the divisions: ObjectBuild.divisions, {index in the loops: (the
    corners choose_sides gave a loop screened whole and not divided,)}: its surface takes them and
    does not choose again). A loop's division (or none) is kept in the cache by its sides' points:
    an edit elsewhere does not screen it again."""
    out, divisions, screened = [], [], {}
    next_id = len(graph.edges)
    for cycle, inside in loops:
        found = None
        if not inside and len(cycle.sides) >= MIN_SIDES:
            sides, own = cycle.polylines_from(polylines), [uses[e] == 1 for e, _ in cycle.sides]
            key = (content_key(*sides), tuple(own))
            kept = cache.lookup("division", key) if cache is not None else None
            if kept is not None:
                found = kept[0]
            else:
                chosen = choose_sides(sides, None, own)
                found = best_division(sides, own, chosen)
                if found is None:
                    screened[len(out)] = (chosen,)
            if cache is not None:
                cache.store("division", key, (found,))
        if found is None:
            out.append((cycle, inside))
            continue
        i, j, across, whole, worse = found
        polylines[next_id] = across
        uses[next_id] = 2
        divisions.append((next_id, side_strokes(graph, [e for e, _ in cycle.sides]), whole, worse))
        sides = tuple(cycle.sides)
        out.append((Cycle(sides[i:j] + ((next_id, True),), cycle.align), []))
        out.append((Cycle(sides[j:] + sides[:i] + ((next_id, False),), cycle.align), []))
        next_id += 1
    return out, divisions, screened


def side_strokes(graph: StrokeGraph, edge_ids) -> list:
    """The input strokes of graph edges, in order; a curve drawn across a divided loop (an id past
    the graph's edges, ObjectBuild.divisions) has none and is left out."""
    return [graph.edges[e].stroke for e in edge_ids if e < len(graph.edges)]


def _curves_key(cycle: Cycle, tangents: dict) -> bytes:
    """A digest of the directions its sides' curves must have at their ends (node_tangents), in loop
    order (not by graph edge id: ids change when a stroke is added elsewhere)."""
    parts = []
    for e, _ in cycle.sides:
        for end in (0, 1):
            t = tangents.get((e, end))
            parts.append(t if t is not None else np.zeros(0))
    return content_key(*parts)


def stroke_network(strokes: Sequence[npt.ArrayLike], tol: Tolerances = Tolerances()) -> tuple:
    """(StrokeGraph, CycleChoice, resolved Tolerances) of a sketch: its strokes validated,
    tolerances resolved from the whole sketch, filtered, and made a network with delta = the
    snap distance."""
    arrays = [validate_stroke(s, i) for i, s in enumerate(strokes)]
    if not arrays:
        raise ProgSurfError("no strokes given; a network needs at least one stroke")
    tol = resolve_tolerances(arrays, tol)
    filtered = [filter_stroke(a, tol.filter_mm) for a in arrays]
    graph = build_stroke_graph(filtered, tol.snap_mm)
    return graph, find_cycles(graph), tol


STEADY_DIGITS = 3
"""steady_tolerances rounds the automatic tolerances to this many significant digits."""


def steady_tolerances(strokes: Sequence[npt.ArrayLike], tol: Tolerances = Tolerances(),
                      digits: int = STEADY_DIGITS) -> Tolerances:
    """`tol` with its automatic (None) filter, snap and fit distances resolved from the sketch
    (core.pipeline.resolve_tolerances) and rounded to `digits` significant digits; given values
    are kept as they are.

    Why: the automatic values follow the sketch's diagonal in its principal axes and its median
    stroke length, which any edit changes in the last bits; every surface depends on them, so an
    edited sketch with exact automatic tolerances rebuilds every surface (BuildCache finds none
    unchanged). Rounded, they stay put unless the edit changes the sketch's size by about 10^-digits,
    and an edited document object (app.network_object) rebuilds only the surfaces its edit touches.
    """
    arrays = [validate_stroke(s, i) for i, s in enumerate(strokes)]
    if not arrays:
        raise ProgSurfError("no strokes given; a network needs at least one stroke")
    full = resolve_tolerances(arrays, tol)

    def steady(given, value):
        return given if given is not None else float(f"{value:.{digits - 1}e}")

    return replace(tol, filter_mm=steady(tol.filter_mm, full.filter_mm), snap_mm=steady(tol.snap_mm, full.snap_mm),
                   fit_mm=steady(tol.fit_mm, full.fit_mm))


def _roles(graph: StrokeGraph, choice: CycleChoice, surfaces: list, failed: list, merged: dict) -> tuple:
    """StrokeRole per input stroke (module docstring); merged: {edge id: the edge it was merged
    into} (core.twice_drawn)."""
    bounds: dict = {}
    inside: dict = {}
    rejected: dict = {}
    for k, surf in enumerate(surfaces):
        for stroke in side_strokes(graph, surf.sides):
            bounds.setdefault(stroke, set()).add(k)
        n = len(surf.result.records) - len(surf.interior)
        for rec, e in zip(surf.result.records[n:], surf.interior):
            stroke = graph.edges[e].stroke
            if rec.status == "accepted":
                inside.setdefault(stroke, set()).add(k)
            else:
                rejected.setdefault(stroke, []).append(f"surface {k} rejected it: {rec.reason}")
    failed_edges = {e: reason for c, reason in failed for e in c.edge_ids}
    twice: dict = {}
    for e, into in merged.items():
        twice.setdefault(graph.edges[e].stroke, set()).add(graph.edges[into].stroke)
    out = []
    for i in range(len(graph.strokes)):
        note = graph.notes.get(i, "")
        if i in twice:
            over = ", ".join(str(k) for k in sorted(twice[i]))
            note = "; ".join(x for x in (note, f"a piece drawn twice with stroke {over} between two nodes: "
                                               f"merged into it") if x)
        reason = note
        if i not in bounds and i not in inside:
            edges = graph.edges_of_stroke(i)
            if rejected.get(i):
                reason = "; ".join(rejected[i])
            elif any(e.id in failed_edges for e in edges):
                reason = "its loop could not be made a surface: " + next(
                    failed_edges[e.id] for e in edges if e.id in failed_edges)
            elif edges and all(e.id in choice.bridges for e in edges):
                reason = ("it joins a group of curves to the loop round them (a bridge): it bounds no "
                          "surface, and is no interior stroke (it would be extended past that group)")
            elif edges and all(e.id in choice.dangling for e in edges):
                reason = "it dangles outside every surface (no loop of curves holds it)"
            elif edges and all(e.id in merged for e in edges):
                reason = note
            elif edges:
                reason = "its pieces bound no surface and lie inside none"
            reason = (note + "; " + reason) if note and reason != note else reason
        out.append(StrokeRole(i, tuple(sorted(bounds.get(i, ()))), tuple(sorted(inside.get(i, ()))), reason))
    return tuple(out)
