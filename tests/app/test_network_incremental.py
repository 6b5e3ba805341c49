"""The SurfaceNetwork feature rebuilds only what an edit touched (issue 18, item 6): after one
stroke object moves, a recompute builds again the surfaces whose strokes changed and keeps the
others (its proxy's core.objects.BuildCache); the result is the one a new network object on the
same strokes gives. A changed tolerance rebuilds every surface; an undo finds its surfaces kept.

unittest classes (pytest and `freecadcmd -t TestProgSurfApp`); each test checks isValid()/State
of what it recomputed, since an exception inside recompute() does not fail a test.
"""
import sys
import unittest

if "/usr/lib/freecad-python3/lib" not in sys.path:
    sys.path.append("/usr/lib/freecad-python3/lib")
import FreeCAD  # noqa: E402,F401  (FreeCAD before Part)

import numpy as np  # noqa: E402

import ProgSurf.app.make as ps  # noqa: E402
from ProgSurf.app.network_object import stroke_accounts  # noqa: E402
from test_network_object import NetworkTestCase, bow_stroke, points_of  # noqa: E402


def poles(face) -> np.ndarray:
    """The poles of a face's B-spline surface: (nu, nv, 3)."""
    return np.array([[tuple(p) for p in row] for row in face.Surface.getPoles()])


class TestIncrementalRecompute(NetworkTestCase):
    def rebuilt(self, net) -> tuple:
        """The surfaces the last recompute built (the others were kept from the one before)."""
        return net.Proxy.outcome.build.rebuilt

    def test_moving_one_stroke_rebuilds_only_the_surfaces_it_touches(self):
        net = self.net
        self.assertEqual(self.rebuilt(net), tuple(range(6)), "the first recompute builds every surface")
        # the automatic tolerances it used, given explicitly: nothing to build again
        tol = net.Proxy.outcome.build.tol
        net.FilterThreshold, net.SnapTolerance, net.FitTolerance = tol.filter_mm, tol.snap_mm, tol.fit_mm
        self.doc.recompute()
        self.assertRecomputed(net)
        self.assertEqual(self.rebuilt(net), ())
        # a changed option rebuilds all
        net.FitTolerance = 0.5 * tol.fit_mm
        self.doc.recompute()
        self.assertRecomputed(net)
        self.assertEqual(self.rebuilt(net), tuple(range(6)))
        plain = list(net.Shape.Faces)

        edge = self.edges[0]                  # (0,0,0)-(0,0,10), bowed outwards between its corners
        old, _ = bow_stroke(self.doc, edge, 1.5, "Bow a stroke")
        self.doc.recompute()
        self.assertRecomputed(net, edge)
        self.assertEqual(net.LastError, "")
        rebuilt = self.rebuilt(net)
        bounds = stroke_accounts(net)[0].boundary_of
        self.assertEqual(len(bounds), 2)
        self.assertTrue(set(bounds) <= set(rebuilt), (bounds, rebuilt))
        self.assertLess(len(rebuilt), 6, "the faces away from the bowed stroke are kept")
        self.assertTrue(net.Shape.isValid())
        self.assertEqual((len(net.Shape.Faces), net.ShellCount, net.ClosedShells), (6, 1, 1))
        # a kept surface's face has the very poles it had; a bowed one's changed
        before = [poles(f) for f in plain]
        for k in range(6):
            now = poles([f for f, owner in zip(net.Shape.Faces, net.FaceSurfaces) if owner == k][0])
            unchanged = any(p.shape == now.shape and np.array_equal(p, now) for p in before)
            self.assertEqual(unchanged, k not in rebuilt, f"surface {k}")

        # a new network object on the same strokes, with the same tolerances, built from scratch
        fresh = ps.make_surface_network(list(net.Strokes), filter_mm=net.FilterThreshold,
                                        snap_mm=net.SnapTolerance, fit_mm=net.FitTolerance)
        self.assertRecomputed(fresh)
        self.assertEqual(self.rebuilt(fresh), tuple(range(6)))
        for name in ("SurfaceCount", "ShellCount", "ClosedShells", "StrokeAccounting", "SurfaceBoundaries",
                     "SurfaceInteriors", "FaceSurfaces", "FailedLoops", "SeamGap", "FitDeviation", "Quality"):
            self.assertEqual(getattr(net, name), getattr(fresh, name), name)
        self.assertAlmostEqual(net.Shape.Area, fresh.Shape.Area, delta=1e-12 * fresh.Shape.Area)
        self.assertAlmostEqual(net.Shape.Volume, fresh.Shape.Volume, delta=1e-12 * abs(fresh.Shape.Volume))

        # undo: every surface is found in the cache (the build before the edit)
        self.doc.undo()
        self.doc.recompute()
        self.assertRecomputed(net, edge)
        np.testing.assert_allclose(points_of(edge), old, atol=1e-12)
        self.assertEqual(self.rebuilt(net), ())
        self.assertEqual(len(net.Shape.Faces), 6)


if __name__ == "__main__":
    unittest.main()
