"""The Stroke feature: one 3D sketch stroke of Qin & Wright (section 2, "arbitrary curves C_k").

A stroke's truth is either its own point list (``Points``, an App::PropertyVectorList, for
imported strokes) or a link (``Source``, App::PropertyLinkSub) to a sketch or to edges, of which
it takes connected chain number ``ChainIndex``. A linked stroke follows its source: moving the
sketch recomputes the stroke and every surface built on it.

Its Shape is the polyline through its points. ``Role``, ``Status`` and ``Reason`` are written
by the surface that uses the stroke (output properties: writing them does not touch the stroke),
and the view provider colours the stroke from them.
"""
from __future__ import annotations

from ProgSurf.core.errors import InvalidStrokeError

from . import extract
from .params import default_tolerances
from .proxy import PROP_OUTPUT, FeatureProxy, add_property

TYPE = "ProgSurf::Stroke"

ROLES = ("", "boundary", "interior")
STATUSES = ("", "accepted", "rejected")


class StrokeProxy(FeatureProxy):
    """Proxy of a Part::FeaturePython stroke. State saved: a tiny JSON-safe dict."""

    PROXY_TYPE = TYPE

    def setup(self, obj) -> None:
        """Create missing properties (new objects and documents saved by older versions)."""
        super().setup(obj)
        add_property(obj, "App::PropertyVectorList", "Points", "Stroke",
                     "Stroke points in mm, global frame (computed from Source when Source is set)")
        add_property(obj, "App::PropertyLinkSub", "Source", "Stroke", "Sketch, wire or edges "
                     "this stroke follows (empty: the stroke owns its Points)")
        add_property(obj, "App::PropertyInteger", "ChainIndex", "Stroke",
                     "Which connected chain of the Source's edges this stroke is (0 = first)")
        add_property(obj, "App::PropertyInteger", "Samples", "Stroke",
                     "Points taken along the Source chain (by arc length)")
        if obj.Samples < 2:
            obj.Samples = default_tolerances().samples
        for name, doc in (("Role", "boundary or interior, set by the surface that uses it"),
                          ("Status", "accepted or rejected, set by the surface that uses it"),
                          ("Reason", "why the surface rejected this stroke")):
            add_property(obj, "App::PropertyString", name, "Result", doc, PROP_OUTPUT,
                         read_only=True)

    def execute(self, obj) -> None:
        """Recompute Points from the Source chain (if linked) and the polyline Shape."""
        if obj.Source:
            source, subnames = obj.Source
            chains = extract.edge_chains(source, subnames, obj.Samples)
            if not 0 <= obj.ChainIndex < len(chains):
                raise InvalidStrokeError(
                    f"stroke {obj.Label!r}: ChainIndex {obj.ChainIndex} but {source.Label!r} "
                    f"has {len(chains)} connected chain(s); set ChainIndex to 0..{len(chains) - 1}")
            obj.Points = extract.array_to_vectors(chains[obj.ChainIndex])
        obj.Shape = extract.polyline_shape(list(obj.Points))


def is_stroke(obj) -> bool:
    """True for a ProgSurf stroke feature."""
    return bool(obj is not None and getattr(obj, "Type", "") == TYPE)


def set_result(obj, role: str, status: str, reason: str) -> None:
    """Write the outcome of a build onto a stroke (does not touch it: output properties)."""
    for name, value in (("Role", role), ("Status", status), ("Reason", reason)):
        if getattr(obj, name) != value:
            setattr(obj, name, value)


def clear_result(obj) -> None:
    set_result(obj, "", "", "")


def stroke_points(obj):
    """The stroke's points as an (n, 3) float array (Qin & Wright's C_k)."""
    return extract.vectors_to_array(obj.Points)

