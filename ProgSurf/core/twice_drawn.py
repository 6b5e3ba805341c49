"""Curves drawn twice between the same two nodes: merged once the strokes are faired (issue 18,
part 1: over-sketched runs merge).

core.stroke_graph merges two edges between the same nodes when the later one lies within delta of
the other along OVERSKETCH_COVER of it (_merge_parallel). It judges the filtered strokes, whose
noise can hold two passes over one curve a little more than delta apart along a quarter of their
length; the chosen cycles then hold a 2-sided loop between them, a lens narrower than the sketch's
tolerance. Fairing (core.fairing) takes the noise out, and the lens collapses: on the 82 CASSIE
sketches of cassie-data not in ../shared, 46 2-sided loops lay within delta of themselves once
faired (HMD 'modern' edges 24 and 54: 0.4-1.1 delta apart as filtered, 0.05 delta faired), and 24
of those surfaces turned over, a lens having no width to span.

Here the faired edges (the polylines every surface takes its sides from,
core.objects.edge_polylines) are judged, both ways: two edges between the same two nodes, each
within SIDE_GAP x delta of the other along OVERSKETCH_COVER of its points, are one curve. That is
the distance under which core.stroke_graph counts two strokes running side by side as touching
(_side_by_side: further apart they are two curves of one family, a boom's guides). On those 82
sketches this drops 34 surfaces, 23 of them reported folding (281 -> 258 folding of 2160 -> 2126);
judged within delta itself it dropped 50, 29 folding: 10 more narrow lenses that built well
went, a shield's crescent ornament 1.0 delta wide among them. The edge kept is that of the earlier
stroke (of one stroke's, the longer: stroke_graph.kept_first), as _merge_parallel keeps; every
chosen cycle takes it in place of the other, and a cycle left with one curve twice (the lens)
bounds nothing and is dropped with the reason. A merge that would make an edge bound more than two
surfaces is not made.
"""
from __future__ import annotations

from dataclasses import replace

from .stroke_cycles import Cycle, CycleChoice
from .stroke_graph import SIDE_GAP, StrokeGraph, covered, kept_first


def _replaced(cycle: Cycle, merged: dict, graph: StrokeGraph) -> tuple:
    """The cycle's sides with each merged edge replaced by the one it was merged into, each still
    running from the node where the previous side ends."""
    out = []
    for e, rev in cycle.sides:
        k = merged.get(e, e)
        if k != e and graph.edges[k].node0 != graph.edges[e].node0:
            rev = not rev
        out.append((k, rev))
    return tuple(out)


def _uses(cycles: list) -> dict:
    uses: dict = {}
    for sides in cycles:
        if len({e for e, _ in sides}) == len(sides):
            for e, _ in sides:
                uses[e] = uses.get(e, 0) + 1
    return uses


def twice_drawn(graph: StrokeGraph, choice: CycleChoice, polylines: dict) -> tuple[CycleChoice, dict]:
    """(the choice with every pair of edges drawn twice merged, {merged edge id: the edge id it was
    merged into}) (module docstring). polylines: edge id -> its faired points (n, 3)."""
    groups: dict = {}
    for e in graph.edges:
        if e.node0 != e.node1:
            groups.setdefault(frozenset((e.node0, e.node1)), []).append(e.id)
    merged: dict = {}
    reach = SIDE_GAP * graph.delta
    for ids in groups.values():
        if len(ids) < 2:
            continue
        kept: list = []
        for e in sorted(ids, key=lambda k: kept_first(graph.edges[k].stroke, polylines[k])):
            into = next((f for f in kept if covered(polylines[e], polylines[f], reach)
                         and covered(polylines[f], polylines[e], reach)), None)
            if into is None:
                kept.append(e)
                continue
            trial = {**merged, e: into}
            if max(_uses([_replaced(c, trial, graph) for c in choice.cycles]).values(), default=0) <= 2:
                merged = trial
            else:
                kept.append(e)
    if not merged:
        return choice, merged
    cycles, dropped = [], list(choice.dropped)
    for cycle in choice.cycles:
        sides = _replaced(cycle, merged, graph)
        if len({e for e, _ in sides}) < len(sides):
            strokes = sorted({graph.edges[e].stroke for e, _ in cycle.sides})
            dropped.append((cycle, f"its sides are one curve drawn twice (strokes {strokes} within "
                                   f"{reach:.3g} mm of each other once faired): merged, no surface "
                                   f"between them"))
        else:
            cycles.append(Cycle(sides, cycle.align))
    return replace(choice, cycles=tuple(cycles), dropped=tuple(dropped)), merged
