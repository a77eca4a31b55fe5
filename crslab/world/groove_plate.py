"""The groove plate as solid boxes: a plate with the Z-shaped channel cut into its top, solid all
round the channel out to the plate's rim (docs/worlds.md, "the groove plate").

The channel is a polygon: the Z's centre line widened by half the groove's width to each side,
mitred at the corners and closed half a width past the entrance and the exit. The plate's top is
the band ``rim_m`` wide outside that polygon, built edge by edge: along each edge of the channel,
boxes in layers (the first 3 mm thick, the rest at most 10 mm), each from the channel's edge
outward. At a corner that turns away from the solid (convex, seen from the channel) a layer runs
on to the mitre, where the next edge's layer meets it; at a corner that turns into the solid
(the inner side of the Z's turns) it stops where its outer face meets the next edge's line, so no
box reaches into the channel; the gaps that leaves are under a millimetre (a test measures
them). A layer that would reach into another leg of the channel (a Z folded tight) is left out,
and so are the layers beyond it. Under the channel, a floor strip along each segment.

>>> from crslab.world.fixtures import Groove
>>> g = Groove(((0.0, 0.0), (0.03, -0.04), (0.0, -0.04), (0.03, -0.08)), 0.225, 0.016, 0.03, 0.02, 0.04)
>>> channel_polygon(g).shape, len(top_boxes(g)), len(floor_boxes(g))
((8, 2), 24, 3)
"""

from __future__ import annotations

import math

import numpy as np

from crslab.world.fixtures import Groove
from crslab.world.shapes import Box

FIRST_LAYER_M = 0.003
"""The layer along the channel's wall: thin, so that the gap it leaves where two walls meet at an
inner corner is under a millimetre."""
MAX_LAYER_M = 0.010
"""The layers beyond it, at most this thick (each leaves a gap near the inner corner's other wall
that the other wall's first layer covers when it is under 3.3 times as thick)."""
FLOOR_OVERLAP_M = 0.003
"""A floor strip reaches this far under the plate's top on each side of the channel."""


def _cross(a: np.ndarray, b: np.ndarray) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


def centre_line(groove: Groove) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The Z's corners (4 x 2), its segments' unit directions and their left normals (3 x 2)."""
    c = np.asarray(groove.corners_xy_m, float)
    d = np.diff(c, axis=0)
    u = d / np.linalg.norm(d, axis=1)[:, None]
    return c, u, np.stack([-u[:, 1], u[:, 0]], axis=1)


def channel_polygon(groove: Groove) -> np.ndarray:
    """The channel's outline in x-y, counterclockwise: 8 corners (the right side's 4 from the
    entrance, the left side's 4 back)."""
    c, u, left = centre_line(groove)
    h = groove.width_m / 2
    ends = [c[0] - u[0] * h, *c[1:-1], c[-1] + u[-1] * h]

    def side(sign: float) -> list[np.ndarray]:
        pts = [ends[0] + sign * h * left[0]]
        for i in (1, 2):
            bisector = left[i - 1] + left[i]
            bisector = bisector / np.linalg.norm(bisector)
            pts.append(ends[i] + sign * bisector * h / float(bisector @ left[i]))
        pts.append(ends[-1] + sign * h * left[-1])
        return pts

    poly = np.array(side(-1.0) + side(1.0)[::-1])
    area = 0.5 * float(np.sum(poly[:, 0] * np.roll(poly[:, 1], -1) - np.roll(poly[:, 0], -1) * poly[:, 1]))
    return poly if area > 0 else poly[::-1]


def _line_t(p: np.ndarray, u: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    """Where the line ``p + t u`` meets the line through ``a`` and ``b``: t."""
    d = b - a
    return _cross(a - p, d) / _cross(u, d)


def _segments_cross(p1: np.ndarray, p2: np.ndarray, q1: np.ndarray, q2: np.ndarray) -> bool:
    """Whether two segments cross at a point inside both (touching ends do not count)."""
    d1, d2 = p2 - p1, q2 - q1
    den = _cross(d1, d2)
    if abs(den) < 1e-15:
        return False
    t, s = _cross(q1 - p1, d2) / den, _cross(q1 - p1, d1) / den
    return 1e-9 < t < 1 - 1e-9 and 1e-9 < s < 1 - 1e-9


def _inside(poly: np.ndarray, point: np.ndarray) -> bool:
    """Whether a point is strictly inside a polygon (ray casting)."""
    x, y = point
    n, hit = len(poly), False
    for i in range(n):
        (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % n]
        if (y1 > y) != (y2 > y) and x < (x2 - x1) * (y - y1) / (y2 - y1) + x1:
            hit = not hit
    return hit


def reaches_into(corners: np.ndarray, channel: np.ndarray) -> bool:
    """Whether the rectangle ``corners`` (4 x 2) shares any area with the channel's polygon."""
    centre = corners.mean(axis=0)
    shrunk = centre + (corners - centre) * (1 - 1e-6)
    rect_edges = [(shrunk[i], shrunk[(i + 1) % 4]) for i in range(4)]
    poly_edges = [(channel[i], channel[(i + 1) % len(channel)]) for i in range(len(channel))]
    if any(_segments_cross(a, b, p, q) for a, b in rect_edges for p, q in poly_edges):
        return True
    return any(_inside(channel, p) for p in shrunk) or any(_inside(shrunk, p) for p in channel)


def _layers(rim: float) -> list[tuple[float, float]]:
    out, at = [], 0.0
    while at < rim - 1e-12:
        step = min(FIRST_LAYER_M if at == 0.0 else MAX_LAYER_M, rim - at)
        out.append((at, at + step))
        at += step
    return out


def top_boxes(groove: Groove) -> list[Box]:
    """The plate's solid around the channel: boxes from the plate's bottom up to its top."""
    poly = channel_polygon(groove)
    n = len(poly)
    bottom = groove.top_z_m - groove.plate_thickness_m
    zc, zh = (bottom + groove.top_z_m) / 2, groove.plate_thickness_m / 2
    boxes = []
    for i in range(n):
        p, q = poly[i], poly[(i + 1) % n]
        before, after = poly[i - 1], poly[(i + 2) % n]
        length = float(np.linalg.norm(q - p))
        u = (q - p) / length
        out = np.array([u[1], -u[0]])  # right of travel: out of a counterclockwise polygon
        for k, (a, b) in enumerate(_layers(groove.rim_m)):
            ends = []
            # at p the edge before (before -> p) meets this one, at q the edge after (q -> after);
            # a left turn of the counterclockwise outline is a convex corner
            for at_end, (r0, r1), convex in (
                (False, (before, p), _cross(p - before, q - p) > 0),
                (True, (q, after), _cross(q - p, after - q) > 0),
            ):
                if convex:  # on to the mitre: where this edge's outer line meets the other edge's
                    uo = (r1 - r0) / np.linalg.norm(r1 - r0)
                    no = np.array([uo[1], -uo[0]])
                    ends.append(_line_t(p + out * b, u, r0 + no * b, r1 + no * b))
                else:  # stop where the layer's outer face meets the other edge's line
                    t_in, t_out = _line_t(p + out * a, u, r0, r1), _line_t(p + out * b, u, r0, r1)
                    ends.append(min(t_in, t_out) if at_end else max(t_in, t_out))
            t0, t1 = ends
            if t1 - t0 <= 1e-9:
                continue
            mid = p + u * (t0 + t1) / 2 + out * (a + b) / 2
            box = Box(
                (float(mid[0]), float(mid[1]), zc),
                ((t1 - t0) / 2, (b - a) / 2, zh),
                math.atan2(u[1], u[0]),
                f"groove_top{i}_{k}",
            )
            if reaches_into(box.corners_xy(), poly):
                break  # this edge's layers from here on would cut into the channel
            boxes.append(box)
    return boxes


def floor_boxes(groove: Groove) -> list[Box]:
    """The channel's floor: a strip along each segment, from the plate's bottom up to the floor,
    reaching past each corner to the channel's mitre."""
    c, u, left = centre_line(groove)
    h = groove.width_m / 2 + FLOOR_OVERLAP_M
    bottom = groove.top_z_m - groove.plate_thickness_m
    zc, zh = (bottom + groove.floor_z_m) / 2, (groove.floor_z_m - bottom) / 2
    boxes = []
    for i in range(3):
        beyond = []
        for j in (i, i + 1):  # at the Z's ends the channel's caps; at a corner the mitre
            if j in (0, 3):
                beyond.append(groove.width_m / 2)
            else:
                turn = math.acos(float(np.clip(u[j - 1] @ u[j], -1.0, 1.0)))
                beyond.append(h * math.tan(turn / 2))
        a, b = c[i] - u[i] * beyond[0], c[i + 1] + u[i] * beyond[1]
        mid = (a + b) / 2
        boxes.append(
            Box(
                (float(mid[0]), float(mid[1]), zc),
                (float(np.linalg.norm(b - a)) / 2, h, zh),
                math.atan2(u[i][1], u[i][0]),
                f"groove_floor{i}",
            )
        )
    return boxes
