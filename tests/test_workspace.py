"""Workspaces (crslab.workspace): reach bounds, the planar 3R dextrous annulus, the PNG."""

import numpy as np
import pytest

from crslab import robots, workspace


def test_reachable_points_stay_within_reach_and_fill_it():
    rrr = robots.load("rrr")
    points = workspace.reachable_points(rrr, 20000)
    rho = np.hypot(points[:, 0], points[:, 1])
    # distance from the shoulder circle (radius a1 = 10 around the base axis) is at most a2 + a3
    assert np.all(np.hypot(rho - 10, points[:, 2]) <= 10 + 1e-9)
    assert points[:, 2].max() > 9.5 and rho.max() > 19.5   # reaches near its outer boundary
    q = workspace.random_configurations(rrr, 1000)
    assert np.all(rrr.chain.within_limits(q))


@pytest.mark.parametrize("links", [(1.0, 1.0, 0.5), (1.0, 0.6, 0.3), (0.5, 1.0, 0.8)])
def test_planar3r_dextrous_grid_is_the_textbook_annulus(links):
    """Dextrous: the circle of radius a3 around p lies in the two-link annulus (seed 001)."""
    a1, a2, a3 = links
    robot = robots.load("planar3r", {"a1": a1, "a2": a2, "a3": a3})
    xy, mask = workspace.dextrous_grid(robot, cells=81, headings=90)
    r = np.hypot(xy[:, 0], xy[:, 1])
    inside = (np.abs(r - a3) >= abs(a1 - a2)) & (r + a3 <= a1 + a2)
    # grid points within a few percent of a boundary may fall either way (finite headings)
    margin = 0.02 * (a1 + a2 + a3)
    clear = np.minimum.reduce([np.abs(np.abs(r - a3) - abs(a1 - a2)), np.abs(r + a3 - (a1 + a2))]) > margin
    assert np.array_equal(mask[clear], inside[clear])
    assert inside.sum() > 0 or a3 > a1 + a2


def test_plots_are_written(tmp_path):
    out = workspace.plot(robots.load("planar3r"), tmp_path / "p.png", n=2000, dextrous=True)
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    out = workspace.plot(robots.load("panda"), tmp_path / "panda.png", n=2000)
    assert out.stat().st_size > 10000
    with pytest.raises(ValueError, match="planar 3R"):
        workspace.plot(robots.load("panda"), tmp_path / "x.png", n=100, dextrous=True)
