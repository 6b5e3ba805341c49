"""PatchNetwork.footpoint searches only the regions whose bounding box can hold the nearest real
footpoint (and every facet only when the nearest regions have none): the answer must be exactly the
one of Eq. 2 over every facet, for points on, near and far from the surface, with and without slack."""
from __future__ import annotations

import numpy as np
import pytest

from benchmarks.surfaces import BENCH_TOL, SURFACES, grow_networks
from ProgSurf.core.footpoint import footpoint


@pytest.fixture(scope="module")
def network():
    nets, _ = grow_networks(SURFACES["saddle"], [60], seed=2, tol=BENCH_TOL)
    net = nets[60]
    assert len(net) >= 60
    return net


@pytest.mark.parametrize("spread", [0.0, 0.5, 5.0, 40.0])
def test_pruned_footpoint_is_the_footpoint_over_every_facet(network, spread):
    z = SURFACES["saddle"]
    rng = np.random.default_rng(int(spread * 10))
    everything = network.facets()
    for i in range(120):
        xy = rng.uniform(-10.0, 110.0, 2)
        q = np.r_[xy, z(*xy) + rng.normal(0.0, spread)]
        slack = (0.0, BENCH_TOL.snap_mm, 0.3)[i % 3]
        fast, full = network.footpoint(q, slack), footpoint(q, everything, slack)
        assert (fast.region, fast.inside, fast.distance) == (full.region, full.inside, full.distance)
        assert np.array_equal(fast.uv, full.uv) and np.array_equal(fast.xyz, full.xyz)
