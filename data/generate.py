#!/usr/bin/env python3
"""Generate BaryLab's bundled example data (data/*.obj, data/*.off, data/bad/*).

Deterministic, standard library only:

    /usr/bin/python3 data/generate.py            # writes next to this script
    /usr/bin/python3 data/generate.py OUT_DIR    # writes into OUT_DIR instead

Every shape is built from fixed parameters (no randomness), every coordinate is
rounded to 6 decimals *before* the geometric checks run, so the checks apply to
exactly what is written.  Any failed check raises AssertionError and nothing is
written.  See data/README.md for what each file is.
"""

import gzip
import math
import os
import sys

# ---------------------------------------------------------------------------
# Parameters (change them here; the README quotes them)
# ---------------------------------------------------------------------------

# 2D gingerbread man -------------------------------------------------------
MODEL2D_SPACING = 0.024     # edge length of the regular triangular grid
MODEL2D_MARGIN = 0.025      # grid vertices kept at least this far inside the cage
MODEL2D_MIN_CLEARANCE = 0.02  # asserted minimum distance model vertex -> cage edge
POSE2D_ARM_DEG = 30.0       # right arm raised about the shoulder
POSE2D_HEAD_DEG = 12.0      # head tilted (counter-clockwise) about the neck
POSE2D_LEG_DEG = -15.0      # left leg kicked outwards about the hip

# 3D kidney -----------------------------------------------------------------
MODEL3D_SUBDIVISIONS = 4    # icosphere level: 10*4^k+2 vertices -> 2562
KIDNEY_RADII = (1.0, 0.55, 0.42)   # half-length (x), half-width (y), half-thickness (z)
KIDNEY_BEND_RADIUS = 1.2    # centre line bent around the z axis, ends curl toward +y
KIDNEY_DENT_DEPTH = 0.40    # hilum dent on the +y side (fraction of half-width)
KIDNEY_DENT_SIZE = (0.35, 0.40)    # dent extent in normalised (x, z)
CAGE3D_RINGS = 7            # rings of the cage along the long axis (+2 pole vertices)
CAGE3D_RING_SIZE = 10       # vertices per ring -> 7*10+2 = 72 vertices, 140 triangles
CAGE3D_OFFSET = (0.16, 0.17, 0.17)  # added to the kidney radii before the cage is built
CAGE3D_MIN_CLEARANCE = 0.05  # asserted minimum distance model vertex -> cage face
POSE3D_SQUEEZE = 0.18       # middle squeezed by 18% across the long axis
POSE3D_BEND_DEG = 30.0      # +x end bent further (about z) by up to 30 degrees
POSE3D_TWIST_DEG = 20.0     # -x end twisted about the long axis by up to 20 degrees

# 3D starfish: a cage of ~100 controls around a model with five limbs (LBC's 3D experiments at
# the paper's scale: locality matters where parts lie far apart along the interior) ------------
STAR_ARMS = 5
STAR_ARMPIT_RADIUS = 0.34   # footprint vertices between the arms
STAR_STATIONS = ((0.55, 0.20, 0.27), (0.85, 0.16, 0.21), (1.15, 0.12, 0.16))
                            # per arm: (distance from the centre, half-width, spine half-height)
STAR_TIP = 1.42             # arm tips (one vertex each, z = 0)
STAR_CENTRE_HEIGHT = 0.34   # half-height at the centre
STAR_SIDE_HEIGHT = 0.7      # half-height of the side and armpit vertices / the spine's
STAR_MODEL_THETA = 80       # model: lat-long sphere, 80 longitudes x 10 latitudes + 2 poles
STAR_MODEL_LAT = 10
STAR_MIN_CLEARANCE = 0.02   # asserted minimum distance model vertex -> cage face

# Organ workflow (issue 15): a liver-like label map and landmarks, in LPS millimetres -------------
ORGAN_DIMS = (112, 96, 72)            # voxels (i: patient's left, j: posterior, k: superior)
ORGAN_SPACING = (1.75, 1.75, 2.5)     # mm: thinner in-plane pixels than axial slices
ORGAN_ORIGIN = (-166.125, -83.375, -205.0)  # LPS mm of voxel (0, 0, 0) (float32-exact)
ORGAN_CENTRE = (-69.0, -0.25, -116.25)   # LPS mm: the grid's centre; the organ's offsets from it
ORGAN_LOBES = (                       # ellipsoids (centre offset, radii) in mm, blended
    ((-28.0, 5.0, 5.0), (52.0, 54.0, 60.0)),     # right lobe (patient's right: -x)
    ((-41.0, -7.0, -39.0), (30.0, 37.0, 25.0)),  # inferior tip of the right lobe
    ((37.0, -16.0, 21.0), (44.0, 30.0, 23.0)),    # left lobe: anterior (-y), superior, flatter
    ((5.0, 21.0, 5.0), (25.0, 23.0, 30.0)))       # caudate, posterior (+y)
ORGAN_BLEND_MM = 9.0                  # smooth-union width (mm)
ORGAN_NOTCH = ((9.0, 30.0, -41.0), (34.0, 28.0, 28.0))  # carved from the visceral side
ORGAN_LOBULATION_MM = 2.5             # amplitude of the surface's gentle undulation
ORGAN_LESION = ((-32.0, 0.0, 14.0), (12.0, 11.0, 10.0))  # label 2, inside the right lobe
ORGAN_LESION_DEPTH_MM = 5.0           # asserted: every lesion voxel this deep in the organ
ORGAN_BORDER_VOXELS = 3               # asserted: no label this close to the image border
ORGAN_BOUND_MM = 130.0                # no organ beyond this distance from the centre (asserted)
ORGAN_DESCRIPTION = "BaryLab synthetic liver: 1 organ, 2 lesion (data/generate.py)"
ORGAN_RAY_START = (-11.0, 5.0, 0.0)   # inside the organ: the dome landmark is seen from here
ORGAN_DOME_RAY = (-0.35, 0.1, 1.0)    # direction (LPS) in which the dome landmark is found
ORGAN_AROUND_MARGIN_MM = (12.0, 12.0, 8.0)  # landmarks around the organ: its bounding box grown
                                      # by this much (x, y, z): their hull holds the organ
ORGAN_BREATH_SHIFT_MM = (12.0, 18.0)  # caudal shift at the inferior-most / superior-most landmark
ORGAN_BREATH_ANTERIOR_MM = 3.0        # anterior shift at the superior-most landmark

DECIMALS = 6


# ---------------------------------------------------------------------------
# Small vector helpers
# ---------------------------------------------------------------------------

def rnd(x):
    """Round to the written precision; normalise -0.0 to 0.0."""
    r = round(x, DECIMALS)
    return 0.0 if r == 0.0 else r


def fmt(x):
    return "%.*f" % (DECIMALS, rnd(x))


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


def scale(a, s):
    return (a[0] * s, a[1] * s, a[2] * s)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def norm(a):
    return math.sqrt(dot(a, a))


def cross2(o, a, b):
    """z component of (a - o) x (b - o)."""
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def rotate2(p, pivot, deg):
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    x, y = p[0] - pivot[0], p[1] - pivot[1]
    return (pivot[0] + c * x - s * y, pivot[1] + s * x + c * y)


def smoothstep(t):
    t = min(1.0, max(0.0, t))
    return t * t * (3.0 - 2.0 * t)


# ---------------------------------------------------------------------------
# 2D geometry checks
# ---------------------------------------------------------------------------

def polygon_area(P):
    """Signed area (positive for counter-clockwise)."""
    n = len(P)
    return 0.5 * sum(P[i][0] * P[(i + 1) % n][1] - P[(i + 1) % n][0] * P[i][1] for i in range(n))


def on_segment(p, a, b):
    return (min(a[0], b[0]) <= p[0] <= max(a[0], b[0]) and
            min(a[1], b[1]) <= p[1] <= max(a[1], b[1]))


def segments_intersect(p1, p2, q1, q2):
    """True if closed segments p1p2 and q1q2 share a point (touching counts)."""
    d1 = cross2(q1, q2, p1)
    d2 = cross2(q1, q2, p2)
    d3 = cross2(p1, p2, q1)
    d4 = cross2(p1, p2, q2)
    if ((d1 > 0 > d2) or (d1 < 0 < d2)) and ((d3 > 0 > d4) or (d3 < 0 < d4)):
        return True
    if d1 == 0 and on_segment(p1, q1, q2):
        return True
    if d2 == 0 and on_segment(p2, q1, q2):
        return True
    if d3 == 0 and on_segment(q1, p1, p2):
        return True
    if d4 == 0 and on_segment(q2, p1, p2):
        return True
    return False


def polygon_self_intersections(P):
    """Pairs of edges (i, j) that intersect although they should not.

    Non-consecutive edges must not touch at all; consecutive edges may only share
    their common vertex (no fold-back / overlap)."""
    n = len(P)
    bad = []
    for i in range(n):
        a, b = P[i], P[(i + 1) % n]
        for j in range(i + 1, n):
            c, d = P[j], P[(j + 1) % n]
            if j == i + 1:          # edges (a,b) and (b,d): d must not lie on ab, a not on bd
                if (cross2(a, b, d) == 0 and on_segment(d, a, b)) or \
                   (cross2(b, d, a) == 0 and on_segment(a, b, d)):
                    bad.append((i, j))
            elif i == 0 and j == n - 1:  # edges (P0,P1) and (P[n-1],P0)
                if (cross2(a, b, c) == 0 and on_segment(c, a, b)) or \
                   (cross2(c, a, b) == 0 and on_segment(b, c, a)):
                    bad.append((i, j))
            elif segments_intersect(a, b, c, d):
                bad.append((i, j))
    return bad


def point_in_polygon(p, P):
    """Crossing-number test (p assumed not on the boundary)."""
    inside = False
    n = len(P)
    x, y = p
    for i in range(n):
        (x1, y1), (x2, y2) = P[i], P[(i + 1) % n]
        if (y1 > y) != (y2 > y):
            xc = x1 + (y - y1) * (x2 - x1) / (y2 - y1)
            if xc > x:
                inside = not inside
    return inside


def dist_point_segment2(p, a, b):
    abx, aby = b[0] - a[0], b[1] - a[1]
    t = ((p[0] - a[0]) * abx + (p[1] - a[1]) * aby) / (abx * abx + aby * aby)
    t = min(1.0, max(0.0, t))
    dx, dy = a[0] + t * abx - p[0], a[1] + t * aby - p[1]
    return math.sqrt(dx * dx + dy * dy)


def dist_to_polygon(p, P):
    n = len(P)
    return min(dist_point_segment2(p, P[i], P[(i + 1) % n]) for i in range(n))


def check_simple_ccw_polygon(P, name):
    assert 12 <= len(P) <= 20, "%s: %d vertices" % (name, len(P))
    bad = polygon_self_intersections(P)
    assert not bad, "%s: self-intersecting edges %s" % (name, bad)
    assert polygon_area(P) > 0, "%s: not counter-clockwise" % name
    convex = all(cross2(P[i - 1], P[i], P[(i + 1) % len(P)]) > 0 for i in range(len(P)))
    assert not convex, "%s: polygon is convex" % name


# ---------------------------------------------------------------------------
# 2D shapes
# ---------------------------------------------------------------------------

# Indices into the gingerbread polygon (used by the pose).
GB_RIGHT_HAND = (5, 6)
GB_HEAD = (8, 9, 10, 11, 12)
GB_LEFT_FOOT = (18, 19)


def gingerbread_cage():
    """A 20-vertex gingerbread man, counter-clockwise, starting at the crotch."""
    right = [
        (0.10, -0.95),   # 1  right foot, inner
        (0.45, -0.95),   # 2  right foot, outer
        (0.30, -0.20),   # 3  right hip
        (0.30, 0.08),    # 4  right armpit
        (0.92, 0.10),    # 5  right hand, bottom
        (0.92, 0.34),    # 6  right hand, top
        (0.14, 0.42),    # 7  right side of the neck
        (0.32, 0.56),    # 8  right cheek
        (0.24, 0.82),    # 9  right temple
    ]
    left = [(-x, y) for (x, y) in reversed(right)]
    P = [(0.0, -0.40)] + right + [(0.0, 0.92)] + left
    # index: 0 crotch, 1-9 right side, 10 top of head, 11-19 left side (mirrored)
    return [(rnd(x), rnd(y)) for (x, y) in P]


def gingerbread_posed(P):
    """Right arm raised, head tilted, left leg kicked out; same vertex order."""
    Q = list(P)
    shoulder = (0.30, 0.22)
    for i in GB_RIGHT_HAND:
        Q[i] = rotate2(P[i], shoulder, POSE2D_ARM_DEG)
    neck = (0.0, 0.42)
    for i in GB_HEAD:   # right cheek, right temple, top, left temple, left cheek
        Q[i] = rotate2(P[i], neck, POSE2D_HEAD_DEG)
    hip = (-0.20, -0.35)
    for i in GB_LEFT_FOOT:
        Q[i] = rotate2(P[i], hip, POSE2D_LEG_DEG)
    return [(rnd(x), rnd(y)) for (x, y) in Q]


# 2D skeleton for bounded biharmonic weights: joints inside the gingerbread man, bones as
# (tail, head) joint pairs; the pose turns bones about their tails by the cage pose's angles.
SKELETON2D_JOINTS = [
    (0.0, -0.15),    # 0 pelvis
    (0.0, 0.36),     # 1 neck
    (0.0, 0.72),     # 2 top of the head
    (0.25, 0.24),    # 3 right shoulder
    (0.82, 0.22),    # 4 right hand
    (-0.25, 0.24),   # 5 left shoulder
    (-0.82, 0.22),   # 6 left hand
    (0.25, -0.85),   # 7 right foot
    (-0.25, -0.85),  # 8 left foot
]
SKELETON2D_BONES = [(0, 1), (1, 2), (1, 3), (3, 4), (1, 5), (5, 6), (0, 7), (0, 8)]
# bone index -> rotation (degrees, counter-clockwise) about its tail
SKELETON2D_POSE = {3: POSE2D_ARM_DEG, 1: POSE2D_HEAD_DEG, 7: POSE2D_LEG_DEG}


def skeleton2d_checks(P):
    """Every joint and every bone sample lies inside the gingerbread polygon, off its boundary."""
    worst = 1e9
    for a, b in SKELETON2D_BONES:
        A, B = SKELETON2D_JOINTS[a], SKELETON2D_JOINTS[b]
        for k in range(101):
            t = k / 100.0
            x = (A[0] + t * (B[0] - A[0]), A[1] + t * (B[1] - A[1]))
            assert point_in_polygon(x, P), "skeleton2d: bone (%d, %d) leaves the cage" % (a, b)
            worst = min(worst, dist_to_polygon(x, P))
    assert worst > 0.03, "skeleton2d: a bone passes within %.4f of the boundary" % worst
    return worst


def tgf_text(joints, bones):
    return ("".join("%d %s %s 0\n" % (i + 1, fmt(x), fmt(y)) for i, (x, y) in enumerate(joints)) +
            "#\n" + "".join("%d %d\n" % (a + 1, b + 1) for a, b in bones) + "#\n")


def skeleton2d_pose_text():
    """One line per bone: a00 a01 t0 a10 a11 t1 (rotation about the bone's tail)."""
    lines = ["# BaryLab pose for skeleton2d.tgf: one 2D affine transform per bone (bone order),\n",
             "# a00 a01 t0 a10 a11 t1; rotations about the bone's tail\n"]
    for b, (tail, _) in enumerate(SKELETON2D_BONES):
        deg = SKELETON2D_POSE.get(b, 0.0)
        c, s_ = math.cos(math.radians(deg)), math.sin(math.radians(deg))
        px, py = SKELETON2D_JOINTS[tail]
        tx, ty = px - (c * px - s_ * py), py - (s_ * px + c * py)
        lines.append("%s %s %s %s %s %s\n" % tuple(fmt(v) for v in (c, -s_, tx, s_, c, ty)))
    return "".join(lines)


class UnionFind:
    def __init__(self, n):
        self.parent = list(range(n))

    def find(self, i):
        while self.parent[i] != i:
            self.parent[i] = self.parent[self.parent[i]]
            i = self.parent[i]
        return i

    def union(self, i, j):
        ri, rj = self.find(i), self.find(j)
        if ri != rj:
            self.parent[max(ri, rj)] = min(ri, rj)


def edge_connected_groups(tris, subset):
    """Groups (lists of triangle indices, in order) of `subset` connected through edges."""
    uf = UnionFind(len(tris))
    owner = {}
    for t in subset:
        a, b, c = tris[t]
        for e in ((a, b), (b, c), (c, a)):
            key = (min(e), max(e))
            if key in owner:
                uf.union(owner[key], t)
            else:
                owner[key] = t
    groups = {}
    for t in subset:
        groups.setdefault(uf.find(t), []).append(t)
    return sorted(groups.values(), key=lambda g: (-len(g), g[0]))


def clean_2d_mesh(tris):
    """Keep the largest edge-connected component and make every vertex manifold
    (its triangles form one fan) by dropping the smaller fans; repeat until stable."""
    keep = list(range(len(tris)))
    while True:
        keep = edge_connected_groups(tris, keep)[0]
        around = {}
        for t in keep:
            for v in tris[t]:
                around.setdefault(v, []).append(t)
        drop = set()
        for v in sorted(around):
            ts = around[v]
            # Fans: triangles around v linked through the edges they share (all contain v).
            uf = UnionFind(len(ts))
            for i in range(len(ts)):
                for j in range(i + 1, len(ts)):
                    if len(set(tris[ts[i]]) & set(tris[ts[j]])) == 2:
                        uf.union(i, j)
            fans = {}
            for i, t in enumerate(ts):
                fans.setdefault(uf.find(i), []).append(t)
            fans = sorted(fans.values(), key=lambda g: (-len(g), g[0]))
            for fan in fans[1:]:
                drop.update(fan)
        if not drop:
            return [tris[t] for t in keep]
        keep = [t for t in keep if t not in drop]


def triangulated_interior(P, spacing, margin):
    """Regular triangular grid clipped to the polygon P offset inwards by `margin`.

    Returns (vertices, triangles) with 0-based, counter-clockwise triangles."""
    xs = [p[0] for p in P]
    ys = [p[1] for p in P]
    dy = spacing * math.sqrt(3.0) / 2.0
    x0, y0 = min(xs), min(ys)
    ni = int(math.ceil((max(xs) - x0) / spacing)) + 2
    nj = int(math.ceil((max(ys) - y0) / dy)) + 2

    def grid_point(i, j):
        return (x0 + (i + 0.5 * (j % 2)) * spacing, y0 + j * dy)

    ok = {}
    for j in range(nj):
        for i in range(ni):
            p = grid_point(i, j)
            ok[(i, j)] = point_in_polygon(p, P) and dist_to_polygon(p, P) >= margin

    tris = []
    for j in range(nj - 1):
        for i in range(ni - 1):
            if j % 2 == 0:
                cand = [((i, j), (i + 1, j), (i, j + 1)), ((i + 1, j), (i + 1, j + 1), (i, j + 1))]
            else:
                cand = [((i, j), (i + 1, j), (i + 1, j + 1)), ((i, j), (i + 1, j + 1), (i, j + 1))]
            for t in cand:
                if all(ok[k] for k in t):
                    tris.append(t)

    # Number the grid points row by row and orient every triangle counter-clockwise.
    keys = sorted({k for t in tris for k in t}, key=lambda k: (k[1], k[0]))
    index = {k: n for n, k in enumerate(keys)}
    V = [grid_point(*k) for k in keys]
    F = []
    for t in tris:
        a, b, c = (index[k] for k in t)
        if cross2(V[a], V[b], V[c]) < 0:
            b, c = c, b
        F.append((a, b, c))

    F = clean_2d_mesh(F)
    used = sorted({v for t in F for v in t})
    remap = {v: n for n, v in enumerate(used)}
    V = [(rnd(V[v][0]), rnd(V[v][1])) for v in used]
    F = [tuple(remap[v] for v in t) for t in F]
    return V, F


def check_model2d(V, F, P):
    assert 1500 <= len(V) <= 4000, "model2d: %d vertices" % len(V)
    for t in F:
        assert cross2(V[t[0]], V[t[1]], V[t[2]]) > 0, "model2d: triangle %s not CCW" % (t,)
    assert len({v for t in F for v in t}) == len(V), "model2d: unreferenced vertices"
    # Edge-manifold with a consistent orientation: each directed edge once, each edge <= 2 faces.
    directed = set()
    for a, b, c in F:
        for e in ((a, b), (b, c), (c, a)):
            assert e not in directed, "model2d: directed edge %s twice" % (e,)
            directed.add(e)
    assert len(edge_connected_groups(F, range(len(F)))) == 1, "model2d: not connected"
    n_edges = len({(min(e), max(e)) for e in directed})
    assert len(V) - n_edges + len(F) == 1, "model2d: not a disk (Euler characteristic != 1)"
    min_clear = float("inf")
    for i, p in enumerate(V):
        assert point_in_polygon(p, P), "model2d: vertex %d outside the cage" % i
        d = dist_to_polygon(p, P)
        assert d >= MODEL2D_MIN_CLEARANCE, "model2d: vertex %d only %g inside" % (i, d)
        min_clear = min(min_clear, d)
    # No mesh edge crosses a cage edge (guards concave cage corners between grid points).
    edges = sorted({(min(a, b), max(a, b)) for t in F for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0]))})
    n = len(P)
    for a, b in edges:
        for k in range(n):
            assert not segments_intersect(V[a], V[b], P[k], P[(k + 1) % n]), \
                "model2d: edge (%d,%d) crosses cage edge %d" % (a, b, k)
    area = sum(0.5 * cross2(V[a], V[b], V[c]) for a, b, c in F)
    return {"min_clearance": min_clear, "area_fraction": area / polygon_area(P)}


# ---------------------------------------------------------------------------
# 3D geometry checks
# ---------------------------------------------------------------------------

def directed_edges_ok(F, name):
    """Closed (each edge in exactly two faces) and consistently oriented (each
    directed edge exactly once)."""
    directed = {}
    for f, (a, b, c) in enumerate(F):
        assert len({a, b, c}) == 3, "%s: face %d repeats a vertex" % (name, f)
        for e in ((a, b), (b, c), (c, a)):
            assert e not in directed, "%s: directed edge %s in faces %d and %d (inconsistent " \
                "orientation or non-manifold)" % (name, e, directed[e], f)
            directed[e] = f
    for (a, b) in directed:
        assert (b, a) in directed, "%s: edge (%d,%d) is a boundary edge (open surface)" % (name, a, b)
    return directed


def vertex_manifold_ok(V, F, name):
    """Every vertex used, and its faces form a single fan (one cycle of edges)."""
    nxt = {}
    for a, b, c in F:
        for v, p, q in ((a, b, c), (b, c, a), (c, a, b)):
            nxt.setdefault(v, {})[p] = q      # around v: p -> q
    assert len(nxt) == len(V), "%s: unreferenced vertices" % name
    for v, ring in nxt.items():
        start = min(ring)
        cur, steps = ring[start], 1
        while cur != start:
            cur = ring[cur]
            steps += 1
        assert steps == len(ring), "%s: vertex %d is not manifold" % (name, v)


def signed_volume(V, F):
    return sum(dot(V[a], cross(V[b], V[c])) for a, b, c in F) / 6.0


def face_normal(V, f):
    a, b, c = (V[i] for i in f)
    return cross(sub(b, a), sub(c, a))


def check_closed_surface(V, F, name, genus=0):
    directed = directed_edges_ok(F, name)
    vertex_manifold_ok(V, F, name)
    euler = len(V) - len(directed) // 2 + len(F)
    assert euler == 2 - 2 * genus, "%s: Euler characteristic %d, not genus %d" % (name, euler, genus)
    for f, t in enumerate(F):
        assert norm(face_normal(V, t)) > 1e-10, "%s: face %d is degenerate" % (name, f)
    vol = signed_volume(V, F)
    assert vol > 0, "%s: signed volume %g is not positive (not outward)" % (name, vol)
    return vol


def concave_edge_count(V, F):
    """Edges where the surface folds inward: the far vertex of one face lies
    in front of the other face's plane."""
    directed = {}
    for f, (a, b, c) in enumerate(F):
        directed[(a, b)] = (f, c)
        directed[(b, c)] = (f, a)
        directed[(c, a)] = (f, b)
    count = 0
    for (a, b), (f, _) in directed.items():
        if a < b:
            _, far = directed[(b, a)]
            n = face_normal(V, F[f])
            if dot(n, sub(V[far], V[a])) > 1e-12:
                count += 1
    return count


def solid_angle(p, a, b, c):
    """Signed solid angle of triangle abc seen from p (Van Oosterom & Strackee)."""
    a, b, c = sub(a, p), sub(b, p), sub(c, p)
    la, lb, lc = norm(a), norm(b), norm(c)
    num = dot(a, cross(b, c))
    den = la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la
    return 2.0 * math.atan2(num, den)


def winding_number(p, V, F):
    return sum(solid_angle(p, V[a], V[b], V[c]) for a, b, c in F) / (4.0 * math.pi)


def dist_point_triangle(p, a, b, c):
    """Distance from p to triangle abc (closest-point regions, Ericson 5.1.5)."""
    ab, ac, ap = sub(b, a), sub(c, a), sub(p, a)
    d1, d2 = dot(ab, ap), dot(ac, ap)
    if d1 <= 0 and d2 <= 0:
        return norm(ap)
    bp = sub(p, b)
    d3, d4 = dot(ab, bp), dot(ac, bp)
    if d3 >= 0 and d4 <= d3:
        return norm(bp)
    vc = d1 * d4 - d3 * d2
    if vc <= 0 and d1 >= 0 and d3 <= 0:
        return norm(sub(p, add(a, scale(ab, d1 / (d1 - d3)))))
    cp = sub(p, c)
    d5, d6 = dot(ab, cp), dot(ac, cp)
    if d6 >= 0 and d5 <= d6:
        return norm(cp)
    vb = d5 * d2 - d1 * d6
    if vb <= 0 and d2 >= 0 and d6 <= 0:
        return norm(sub(p, add(a, scale(ac, d2 / (d2 - d6)))))
    va = d3 * d6 - d5 * d4
    if va <= 0 and (d4 - d3) >= 0 and (d5 - d6) >= 0:
        w = (d4 - d3) / ((d4 - d3) + (d5 - d6))
        return norm(sub(p, add(b, scale(sub(c, b), w))))
    denom = 1.0 / (va + vb + vc)
    v, w = vb * denom, vc * denom
    return norm(sub(p, add(a, add(scale(ab, v), scale(ac, w)))))


EPS = 1e-12


def segment_hits_triangle(p, q, a, b, c):
    """True if the segment pq crosses the (closed) triangle abc, not coplanar case."""
    n = cross(sub(b, a), sub(c, a))
    dp, dq = dot(n, sub(p, a)), dot(n, sub(q, a))
    if (dp > EPS and dq > EPS) or (dp < -EPS and dq < -EPS):
        return False
    if abs(dp - dq) <= EPS:           # parallel to the plane (coplanar handled elsewhere)
        return False
    t = dp / (dp - dq)
    x = add(p, scale(sub(q, p), t))
    # x inside abc (closed)?
    s1 = dot(n, cross(sub(b, a), sub(x, a)))
    s2 = dot(n, cross(sub(c, b), sub(x, b)))
    s3 = dot(n, cross(sub(a, c), sub(x, c)))
    tol = -1e-12 * dot(n, n)
    return s1 >= tol and s2 >= tol and s3 >= tol


def coplanar(V, f, g):
    n = face_normal(V, f)
    ln = norm(n)
    return all(abs(dot(n, sub(V[v], V[f[0]]))) <= 1e-9 * ln for v in g)


def coplanar_overlap(V, f, g):
    """2D overlap test of two coplanar triangles (interiors overlapping)."""
    n = face_normal(V, f)
    ax = max(range(3), key=lambda i: abs(n[i]))
    u, w = [(1, 2), (0, 2), (0, 1)][ax]
    A = [(V[i][u], V[i][w]) for i in f]
    B = [(V[i][u], V[i][w]) for i in g]
    shared = set(f) & set(g)
    for i in range(3):
        for j in range(3):
            ei, ej = (f[i], f[(i + 1) % 3]), (g[j], g[(j + 1) % 3])
            if set(ei) & set(ej):
                continue
            if segments_intersect(A[i], A[(i + 1) % 3], B[j], B[(j + 1) % 3]):
                return True

    def inside(p, T):
        s = [cross2(T[k], T[(k + 1) % 3], p) for k in range(3)]
        return all(x > 0 for x in s) or all(x < 0 for x in s)
    for k, v in enumerate(g):
        if v not in shared and inside(B[k], A):
            return True
    for k, v in enumerate(f):
        if v not in shared and inside(A[k], B):
            return True
    return False


def triangles_intersect(V, f, g):
    """Intersection test for two faces, ignoring contact along what they share."""
    shared = set(f) & set(g)
    if len(shared) == 2:
        # Two planes through the common edge meet only along it, unless the faces fold flat.
        nf, ng = face_normal(V, f), face_normal(V, g)
        return dot(nf, ng) <= -(1.0 - 1e-9) * norm(nf) * norm(ng)
    if coplanar(V, f, g):
        return coplanar_overlap(V, f, g)
    if len(shared) == 1:
        # Edges through the shared vertex can meet the other plane only there; test the
        # opposite edges.
        s = next(iter(shared))
        ef = [v for v in f if v != s]
        eg = [v for v in g if v != s]
        return (segment_hits_triangle(V[ef[0]], V[ef[1]], *(V[v] for v in g)) or
                segment_hits_triangle(V[eg[0]], V[eg[1]], *(V[v] for v in f)))
    for (x, y) in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0])):
        if segment_hits_triangle(V[x], V[y], *(V[v] for v in g)):
            return True
    for (x, y) in ((g[0], g[1]), (g[1], g[2]), (g[2], g[0])):
        if segment_hits_triangle(V[x], V[y], *(V[v] for v in f)):
            return True
    return False


def self_intersections(V, F):
    """All pairs of faces that intersect other than along shared edges/vertices.
    Brute force over pairs whose bounding boxes overlap (sweep along x)."""
    boxes = []
    for f in F:
        pts = [V[i] for i in f]
        boxes.append((tuple(min(p[k] for p in pts) for k in range(3)),
                      tuple(max(p[k] for p in pts) for k in range(3))))
    order = sorted(range(len(F)), key=lambda i: (boxes[i][0][0], i))
    bad, active, tested = [], [], 0
    for i in order:
        lo, hi = boxes[i]
        active = [j for j in active if boxes[j][1][0] >= lo[0]]
        for j in active:
            lo2, hi2 = boxes[j]
            if lo2[1] > hi[1] or hi2[1] < lo[1] or lo2[2] > hi[2] or hi2[2] < lo[2]:
                continue
            tested += 1
            if triangles_intersect(V, F[i], F[j]):
                bad.append((min(i, j), max(i, j)))
        active.append(i)
    return sorted(bad), tested


def check_no_self_intersections(V, F, name):
    bad, tested = self_intersections(V, F)
    assert not bad, "%s: intersecting faces %s" % (name, bad[:10])
    return tested


# ---------------------------------------------------------------------------
# 3D shapes
# ---------------------------------------------------------------------------

def icosphere(levels):
    """Unit icosphere, outward counter-clockwise faces, deterministic vertex order."""
    t = (1.0 + math.sqrt(5.0)) / 2.0
    V = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0),
         (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    F = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11),
         (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6), (7, 1, 8),
         (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9),
         (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    V = [scale(v, 1.0 / norm(v)) for v in V]
    for _ in range(levels):
        mid = {}

        def midpoint(a, b):
            key = (min(a, b), max(a, b))
            if key not in mid:
                m = scale(add(V[a], V[b]), 0.5)
                V.append(scale(m, 1.0 / norm(m)))
                mid[key] = len(V) - 1
            return mid[key]
        G = []
        for a, b, c in F:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            G += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        F = G
    return V, F


def bend(p, radius=KIDNEY_BEND_RADIUS):
    """Bend the x axis into an arc of the given radius around the z axis, curling
    the ends toward +y. (0, y, z) is fixed; injective while y < radius and
    |x| < pi * radius."""
    x, y, z = p
    phi = x / radius
    r = radius - y
    return (r * math.sin(phi), radius - r * math.cos(phi), z)


def kidney_straight(p):
    """Unit-sphere point -> unbent kidney: ellipsoid with a hilum dent on +y.

    y -> y * (1 - D g(x,z) s(y)) is strictly increasing in y (D (s + y s') < 1), so
    the map is injective and the surface stays embedded."""
    x, y, z = p
    sx, sz = KIDNEY_DENT_SIZE
    g = math.exp(-((x / sx) ** 2 + (z / sz) ** 2))
    s = 1.0 / (1.0 + math.exp(-y / 0.15))
    y = y * (1.0 - KIDNEY_DENT_DEPTH * g * s)
    a, b, c = KIDNEY_RADII
    return (a * x, b * y, c * z)


# 3D organ for celestial coordinates: a heart-like closed surface, free control points around it
# (14 active ones + 8 fixed hull points), and a scripted heartbeat of the active ones.
HEART_FRAMES = 20                 # frames per beat
HEART_VENTRICLE_SQUEEZE = 0.18    # radial contraction of the ventricle ring and apex (systole)
HEART_ATRIUM_SQUEEZE = 0.12       # radial contraction of the atrium ring, half a beat later
HEART_APEX_LIFT = 0.10            # the apex moves up towards the base in systole
HEART_HULL = (1.3, 1.2, 1.25)     # half-extents of the box whose corners are the hull points


def heart_shape(p):
    """Unit-sphere point -> heart-like surface: wide base at +z, narrower apex at -z tilted
    to -x. Each z-slice is scaled (positive factor) and sheared, z is scaled: injective."""
    x, y, z = p
    w = 0.72 + 0.28 * z
    tilt = -0.18 * ((1.0 - z) / 2.0) ** 2
    return (0.62 * w * x + tilt, 0.52 * w * y, 0.78 * z)


def heart_model():
    S, F = icosphere(MODEL3D_SUBDIVISIONS)
    return [heart_shape(p) for p in S], F


def heart_controls():
    """14 active controls (6 on an atrium ring, 6 on a ventricle ring, apex, top), then the 8
    hull points (box corners), which the heartbeat leaves in place."""
    C = []
    for k in range(6):
        a = 2.0 * math.pi * k / 6.0
        C.append((0.95 * math.cos(a), 0.80 * math.sin(a), 0.55))
    for k in range(6):
        a = 2.0 * math.pi * (k + 0.5) / 6.0
        C.append((-0.05 + 0.80 * math.cos(a), 0.68 * math.sin(a), -0.20))
    C.append((-0.22, 0.0, -0.95))   # apex
    C.append((0.0, 0.0, 0.95))      # top of the base
    hx, hy, hz = HEART_HULL
    for sx in (-1, 1):
        for sy in (-1, 1):
            for sz in (-1, 1):
                C.append((sx * hx, sy * hy, sz * hz))
    return [tuple(rnd(v) for v in c) for c in C]


def heartbeat_frame(C, t):
    """Control points at beat phase t in [0, 1): ventricles squeeze first, atria half a beat
    later; hull points fixed."""
    sv = HEART_VENTRICLE_SQUEEZE * math.sin(math.pi * t) ** 2
    sa = HEART_ATRIUM_SQUEEZE * math.sin(math.pi * (t + 0.5)) ** 2
    Q = []
    for i, (x, y, z) in enumerate(C):
        if i < 6:
            Q.append((x * (1 - sa), y * (1 - sa), z))
        elif i < 12:
            Q.append((-0.05 + (x + 0.05) * (1 - sv), y * (1 - sv), z))
        elif i == 12:
            Q.append((x * (1 - sv), y, z + HEART_APEX_LIFT * math.sin(math.pi * t) ** 2))
        else:
            Q.append((x, y, z))
    return [tuple(rnd(v) for v in q) for q in Q]


def hull_facets(P):
    """Facets of the convex hull of a small 3D point set (brute force over triples): list of
    (outward unit normal n, offset d) with n.x <= d inside."""
    facets = []
    n = len(P)
    for i in range(n):
        for j in range(i + 1, n):
            for k in range(j + 1, n):
                nrm = cross(sub(P[j], P[i]), sub(P[k], P[i]))
                ln = norm(nrm)
                if ln < 1e-12:
                    continue
                nrm = scale(nrm, 1.0 / ln)
                d = dot(nrm, P[i])
                side = [dot(nrm, P[m]) - d for m in range(n)]
                if all(v <= 1e-12 for v in side):
                    facets.append((nrm, d))
                elif all(v >= -1e-12 for v in side):
                    facets.append((scale(nrm, -1.0), -d))
    return facets


def check_inside_hull(V, C, name):
    """Every point of V strictly inside the convex hull of C; returns the smallest margin."""
    facets = hull_facets(C)
    assert len(facets) >= 4, name + ": degenerate hull"
    margin = min(d - dot(nrm, v) for v in V for nrm, d in facets)
    assert margin > 0.05, "%s: a model vertex is within %.4f of the controls' hull" % (name, margin)
    return margin


def kidney_model():
    S, F = icosphere(MODEL3D_SUBDIVISIONS)
    V = [bend(kidney_straight(p)) for p in S]
    return V, F


def ring_tube(rings, ring_size, radii):
    """A closed ring-and-pole triangle mesh around the x axis, in the unbent frame:
    `rings` elliptical rings at x = -a cos(t_k) with half-axes (b sin t_k, c sin t_k),
    plus one pole vertex at each end. Vertex 0 is the -x pole, the last the +x pole."""
    a, b, c = radii
    V = [(-a, 0.0, 0.0)]
    for k in range(1, rings + 1):
        t = math.pi * k / (rings + 1)
        for m in range(ring_size):
            th = 2.0 * math.pi * (m + 0.5 * (k % 2)) / ring_size
            V.append((-a * math.cos(t), b * math.sin(t) * math.cos(th), c * math.sin(t) * math.sin(th)))
    V.append((a, 0.0, 0.0))
    last = len(V) - 1

    def ring(k, m):
        return 1 + (k - 1) * ring_size + (m % ring_size)
    F = []
    for m in range(ring_size):
        F.append((0, ring(1, m + 1), ring(1, m)))
    for k in range(1, rings):
        for m in range(ring_size):
            a0, a1 = ring(k, m), ring(k, m + 1)
            b0, b1 = ring(k + 1, m), ring(k + 1, m + 1)
            if k % 2 == 0:   # ring k+1 is half a step ahead: b0 lies between a0 and a1
                F += [(a0, a1, b0), (a1, b1, b0)]
            else:            # ring k+1 is half a step behind: b1 lies between a0 and a1
                F += [(a0, b1, b0), (a0, a1, b1)]
    for m in range(ring_size):
        F.append((last, ring(rings, m), ring(rings, m + 1)))
    return V, F


def kidney_cage_straight():
    radii = tuple(r + o for r, o in zip(KIDNEY_RADII, CAGE3D_OFFSET))
    return ring_tube(CAGE3D_RINGS, CAGE3D_RING_SIZE, radii)


def kidney_cage():
    S, F = kidney_cage_straight()
    return [bend(p) for p in S], F


def kidney_cage_posed():
    """Same cage, deformed in the unbent frame before bending:
    - the middle is squeezed across the long axis (y, z scaled down around x = 0),
    - the -x end is twisted about the long axis,
    and after bending the +x end is bent further about the z axis."""
    S, F = kidney_cage_straight()
    a = KIDNEY_RADII[0] + CAGE3D_OFFSET[0]
    out = []
    for (x, y, z) in S:
        sq = 1.0 - POSE3D_SQUEEZE * math.exp(-(x / 0.45) ** 2)
        y, z = y * sq, z * sq
        tw = math.radians(POSE3D_TWIST_DEG) * smoothstep((-x - 0.1) / (a - 0.1))
        y, z = y * math.cos(tw) - z * math.sin(tw), y * math.sin(tw) + z * math.cos(tw)
        p = bend((x, y, z))
        # Extra bend of the +x end about the z axis through the bent centre line at x = 0.2.
        al = math.radians(POSE3D_BEND_DEG) * smoothstep((x - 0.2) / (a - 0.2))
        pivot = bend((0.2, 0.0, 0.0))
        q = rotate2((p[0], p[1]), (pivot[0], pivot[1]), math.degrees(al))
        out.append((q[0], q[1], p[2]))
    return out, F


def center_and_round(Vs, shift):
    return [[tuple(rnd(v[k] - shift[k]) for k in range(3)) for v in V] for V in Vs]


def check_cage_encloses(model, cage_V, cage_F):
    min_d, min_w, max_w = float("inf"), float("inf"), -float("inf")
    for i, p in enumerate(model):
        w = winding_number(p, cage_V, cage_F)
        assert abs(w - 1.0) < 1e-6, "cage3d: model vertex %d has winding number %g" % (i, w)
        min_w, max_w = min(min_w, w), max(max_w, w)
        d = min(dist_point_triangle(p, *(cage_V[v] for v in f)) for f in cage_F)
        assert d >= CAGE3D_MIN_CLEARANCE, "cage3d: model vertex %d only %g inside" % (i, d)
        min_d = min(min_d, d)
    return min_d


# ---------------------------------------------------------------------------
# 3D starfish: cage and model
# ---------------------------------------------------------------------------

def starfish_cage():
    """A 2.5D cage: a planar triangulation of a five-armed star (the centre, one vertex between
    each two arms, per arm three stations of right / spine / left vertices and a tip), lifted
    to a top cap z = +h and a bottom cap z = -h over the same triangles, joined by vertical
    side walls; the tips (h = 0) belong to both caps. Each cap is the graph of a positive
    function over a valid triangulation (every footprint triangle counter-clockwise, total area
    = the outline's area) and the walls stand on the outline, so the surface is embedded."""
    n = STAR_ARMS
    P, H = [], []

    def vertex(p, h):
        P.append(p)
        H.append(h)
        return len(P) - 1
    c = vertex((0.0, 0.0), STAR_CENTRE_HEIGHT)
    pits = []
    for k in range(n):
        a = 2.0 * math.pi * (k + 0.5) / n
        pits.append(vertex((STAR_ARMPIT_RADIUS * math.cos(a), STAR_ARMPIT_RADIUS * math.sin(a)),
                           STAR_SIDE_HEIGHT * STAR_CENTRE_HEIGHT))
    arms = []
    for k in range(n):
        a = 2.0 * math.pi * k / n
        u, v = (math.cos(a), math.sin(a)), (-math.sin(a), math.cos(a))
        stations = []
        for d, w, h in STAR_STATIONS:
            right = vertex((d * u[0] - w * v[0], d * u[1] - w * v[1]), STAR_SIDE_HEIGHT * h)
            spine = vertex((d * u[0], d * u[1]), h)
            left = vertex((d * u[0] + w * v[0], d * u[1] + w * v[1]), STAR_SIDE_HEIGHT * h)
            stations.append((right, spine, left))
        arms.append((stations, vertex((STAR_TIP * u[0], STAR_TIP * u[1]), 0.0)))
    tris = []
    for k in range(n):
        stations, tip = arms[k]
        before, after = pits[k - 1], pits[k]
        tris.append((c, before, after))
        r1, s1, l1 = stations[0]
        tris += [(before, r1, s1), (before, s1, after), (after, s1, l1)]
        for (r0, s0, l0), (r1, s1, l1) in zip(stations, stations[1:]):
            tris += [(r0, r1, s1), (r0, s1, s0), (s0, s1, l1), (s0, l1, l0)]
        r, s, l = stations[-1]
        tris += [(r, tip, s), (s, tip, l)]
    for t in tris:
        assert cross2(*(P[i] for i in t)) > 1e-6, "starfish_cage: footprint triangle %s" % (t,)
    outline = []
    for k in range(n):
        stations, tip = arms[k]
        outline += [pits[k - 1]] + [st[0] for st in stations] + [tip] + \
            [st[2] for st in reversed(stations)]
    area = sum(0.5 * cross2(*(P[i] for i in t)) for t in tris)
    bad = polygon_self_intersections([P[i] for i in outline])
    assert not bad, "starfish_cage: self-intersecting footprint outline %s" % (bad,)
    assert abs(area - polygon_area([P[i] for i in outline])) < 1e-9, \
        "starfish_cage: footprint triangles do not tile the outline"
    V, top, bottom = [], {}, {}
    for i, (p, h) in enumerate(zip(P, H)):
        top[i] = len(V)
        V.append((p[0], p[1], h))
        if h > 0:
            bottom[i] = len(V)
            V.append((p[0], p[1], -h))
        else:
            bottom[i] = top[i]
    F = [tuple(top[i] for i in t) for t in tris]
    F += [(bottom[a], bottom[c2], bottom[b]) for a, b, c2 in tris]
    for q in range(len(outline)):
        a, b = outline[q], outline[(q + 1) % len(outline)]
        if H[b] == 0:
            F.append((bottom[a], top[b], top[a]))
        elif H[a] == 0:
            F.append((top[a], bottom[b], top[b]))
        else:
            F += [(bottom[a], bottom[b], top[b]), (bottom[a], top[b], top[a])]
    return [tuple(rnd(x) for x in p) for p in V], F


def starfish_radius(theta):
    """The model's outline in the plane z = 0: five arms at theta = 2 pi k / 5."""
    return 0.24 + ((0.5 + 0.5 * math.cos(STAR_ARMS * theta)) ** 3)


def starfish_model():
    """A lat-long unit sphere mapped by (rho, theta, z) -> (rho R(theta), theta, z h(rho
    R(theta))) (cylindrical coordinates, R and h positive): for fixed theta, rho -> rho R is
    increasing and z is scaled by a positive factor, so the map is injective."""
    nt, nl = STAR_MODEL_THETA, STAR_MODEL_LAT
    S = [(0.0, 0.0, -1.0)]
    for i in range(1, nl + 1):
        psi = -math.pi / 2.0 + math.pi * i / (nl + 1)
        for j in range(nt):
            th = 2.0 * math.pi * j / nt
            S.append((math.cos(psi) * math.cos(th), math.cos(psi) * math.sin(th), math.sin(psi)))
    S.append((0.0, 0.0, 1.0))
    last = len(S) - 1

    def ring(i, j):
        return 1 + (i - 1) * nt + j % nt
    F = [(0, ring(1, j + 1), ring(1, j)) for j in range(nt)]
    for i in range(1, nl):
        for j in range(nt):
            F += [(ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)),
                  (ring(i, j), ring(i + 1, j + 1), ring(i + 1, j))]
    F += [(last, ring(nl, j), ring(nl, j + 1)) for j in range(nt)]
    V = []
    for x, y, z in S:
        th = math.atan2(y, x)
        r = math.hypot(x, y) * starfish_radius(th)
        h = 0.22 - 0.12 * min(r, 1.24) / 1.24
        V.append((r * math.cos(th), r * math.sin(th), z * h))
    return [tuple(rnd(x) for x in p) for p in V], F


def check_starfish_encloses(model_V, model_F, cage_V, cage_F):
    """Every model vertex inside the cage (winding number 1, at least STAR_MIN_CLEARANCE from
    every cage face) and no model face meets a cage face: the model surface is inside."""
    min_d = float("inf")
    for i, p in enumerate(model_V):
        w = winding_number(p, cage_V, cage_F)
        assert abs(w - 1.0) < 1e-6, "starfish: model vertex %d has winding number %g" % (i, w)
        d = min(dist_point_triangle(p, *(cage_V[v] for v in f)) for f in cage_F)
        assert d >= STAR_MIN_CLEARANCE, "starfish: model vertex %d only %g inside" % (i, d)
        min_d = min(min_d, d)
    V = list(cage_V) + list(model_V)
    offset = len(cage_V)

    def box(f):
        pts = [V[i] for i in f]
        return [min(p[k] for p in pts) for k in range(3)], [max(p[k] for p in pts) for k in range(3)]
    cage_boxes = [(f, box(f)) for f in cage_F]
    tested = 0
    for g in model_F:
        g = tuple(i + offset for i in g)
        lo, hi = box(g)
        for f, (flo, fhi) in cage_boxes:
            if any(flo[k] > hi[k] or fhi[k] < lo[k] for k in range(3)):
                continue
            tested += 1
            assert not triangles_intersect(V, f, g), "starfish: model face meets cage face %s" % (f,)
    return min_d, tested


# ---------------------------------------------------------------------------
# Intentionally broken inputs
# ---------------------------------------------------------------------------

CUBE_V = [(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1),
          (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)]
CUBE_QUADS = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4),
              (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]   # outward, 0-based


def cube_triangles():
    F = []
    for a, b, c, d in CUBE_QUADS:
        F += [(a, b, c), (a, c, d)]
    return F


def bad_files():
    """name -> text. Also asserts that each file is broken in the intended way."""
    V = [tuple(float(x) for x in v) for v in CUBE_V]
    tris = cube_triangles()
    check_closed_surface(V, tris, "cube")            # the unbroken base is valid

    def obj(Vs, Fs, vstr=None):
        lines = [vstr(i, v) if vstr else "v %s %s %s" % tuple(fmt(x) for x in v)
                 for i, v in enumerate(Vs)]
        lines += ["f " + " ".join(str(i + 1) for i in f) for f in Fs]
        return "\n".join(lines) + "\n"

    files = {}
    # open: the top side (+z, quad 1 = two triangles) removed -> 4 boundary edges.
    open_F = [t for k, t in enumerate(tris) if k not in (2, 3)]
    try:
        directed_edges_ok(open_F, "open")
        raise RuntimeError("open_cage is not open")
    except AssertionError:
        pass
    files["bad/open_cage.obj"] = obj(V, open_F)

    # nan: valid closed cube, vertex 7 (1-based) has y = nan.
    files["bad/nan_cage.obj"] = obj(V, tris, lambda i, v: "v %s %s %s" % (
        fmt(v[0]), "nan" if i == 6 else fmt(v[1]), fmt(v[2])))

    # bowtie: figure-of-eight quadrilateral, edges 0 and 2 cross at the origin.
    bow = [(-0.5, -0.5), (0.5, 0.5), (0.5, -0.5), (-0.5, 0.5)]
    assert polygon_self_intersections(bow), "bowtie is simple?"
    files["bad/bowtie2d.obj"] = "".join("v %s %s 0\n" % (fmt(x), fmt(y)) for x, y in bow)

    # inconsistent: the 5th triangle (first of the -y side) has reversed winding.
    inc = list(tris)
    a, b, c = inc[4]
    inc[4] = (a, c, b)
    try:
        directed_edges_ok(inc, "inconsistent")
        raise RuntimeError("inconsistent_cage is consistent")
    except AssertionError:
        pass
    files["bad/inconsistent_cage.obj"] = obj(V, inc)

    # quads: closed, outward cube with 6 quadrilateral faces.
    files["bad/quad_cage.obj"] = obj(V, CUBE_QUADS)

    files["bad/empty.obj"] = ""
    files["bad/garbage.off"] = ("this is not an OFF file\n"
                                "OF F 8 6 0\n"
                                "1.0 two 3,0 @@@ -- ~~\n"
                                "\x7fgarbage\tfields 1e999999 0x1p3\n")
    return files


# ---------------------------------------------------------------------------
# Writers
# ---------------------------------------------------------------------------

def obj_polygon_text(P):
    return "".join("v %s %s 0\n" % (fmt(x), fmt(y)) for x, y in P)


def obj_mesh2d_text(V, F):
    return ("".join("v %s %s 0\n" % (fmt(x), fmt(y)) for x, y in V) +
            "".join("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in F))


def obj_mesh3d_text(V, F):
    return ("".join("v %s %s %s\n" % tuple(fmt(x) for x in v) for v in V) +
            "".join("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in F))


def off_text(V, F):
    return ("OFF\n%d %d 0\n" % (len(V), len(F)) +
            "".join("%s %s %s\n" % tuple(fmt(x) for x in v) for v in V) +
            "".join("3 %d %d %d\n" % f for f in F))


# ---------------------------------------------------------------------------

# Picture for the viewer's 2D image mode ---------------------------------------
IMAGE2D_SIZE = 256          # pixels per side of gingerbread.png
IMAGE2D_MARGIN = 0.05       # the picture covers the cage's bounding box enlarged by 5% per side


def png_bytes(width, height, rgb_rows, channels=3):
    """A minimal 8-bit PNG (standard library only: zlib, struct): truecolour rows of r, g, b
    values (channels=3) or greyscale rows of one value per pixel (channels=1)."""
    import struct
    import zlib

    def chunk(kind, payload):
        body = kind + payload
        return struct.pack(">I", len(payload)) + body + struct.pack(">I", zlib.crc32(body) & 0xFFFFFFFF)

    raw = b"".join(b"\x00" + bytes(row) for row in rgb_rows)
    return (b"\x89PNG\r\n\x1a\n"
            + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, {3: 2, 1: 0}[channels], 0, 0, 0))
            + chunk(b"IDAT", zlib.compress(raw, 9))
            + chunk(b"IEND", b""))


def gingerbread_picture(P):
    """A gingerbread man drawn over his cage, for texture warping: brown dough inside the cage,
    white icing along the limbs, eyes, mouth and buttons, a thin grid every 0.1 units so the
    deformation shows, a blue checkerboard outside. Pixel (i, j) (i = column, j = row from the
    top) sits at the world point the viewer maps it to: the square image covers the cage's
    bounding box enlarged by IMAGE2D_MARGIN per side, centred, aspect kept (it covers the box)."""
    xs = [p[0] for p in P]
    ys = [p[1] for p in P]
    w = (max(xs) - min(xs)) * (1 + 2 * IMAGE2D_MARGIN)
    h = (max(ys) - min(ys)) * (1 + 2 * IMAGE2D_MARGIN)
    side = max(w, h)
    cx, cy = 0.5 * (max(xs) + min(xs)), 0.5 * (max(ys) + min(ys))
    n = IMAGE2D_SIZE
    features = [((-0.09, 0.70), 0.035, (40, 25, 15)),    # eyes
                ((0.09, 0.70), 0.035, (40, 25, 15)),
                ((0.0, 0.22), 0.04, (200, 30, 40)),      # buttons
                ((0.0, 0.02), 0.04, (40, 140, 60)),
                ((0.0, -0.18), 0.04, (60, 80, 200))]
    rows = []
    for j in range(n):
        row = []
        y = cy + side * (0.5 - (j + 0.5) / n)
        for i in range(n):
            x = cx + side * ((i + 0.5) / n - 0.5)
            if point_in_polygon((x, y), P):
                colour = (181, 110, 50)
                if abs(abs(x) - 0.62) < 0.03 and 0.1 < y < 0.36:       # icing on the arms
                    colour = (250, 250, 245)
                if abs(y + 0.75) < 0.025 and 0.05 < abs(x) < 0.42:     # icing on the legs
                    colour = (250, 250, 245)
                mouth = math.hypot(x, y - 0.66)
                if abs(mouth - 0.1) < 0.015 and y < 0.62:
                    colour = (120, 40, 30)
                for (fx, fy), r, c in features:
                    if math.hypot(x - fx, y - fy) < r:
                        colour = c
                gx, gy = x * 10 - round(x * 10), y * 10 - round(y * 10)
                if min(abs(gx), abs(gy)) < 0.06:
                    colour = tuple(int(0.75 * v) for v in colour)
            else:
                checker = (int(math.floor(x * 5)) + int(math.floor(y * 5))) % 2
                colour = (200, 220, 245) if checker else (225, 235, 250)
            row.extend(colour)
        rows.append(row)
    return png_bytes(n, n, rows)

# Weighted averages on surfaces: a bumpy torus ---------------------------------------------
WA_TORUS_N = 72        # samples around the central circle (u)
WA_TORUS_M = 28        # samples around the tube (v)
WA_TORUS_R = 1.0       # central radius
WA_TORUS_TUBE = 0.4    # tube radius before the bumps
WA_TORUS_BUMP = 0.15   # relative bump height: tube radius x (1 + bump sin(3u) cos(2v))
# Anchors: vertices (i, j) of the grid, a 3 x 3 patch on the outer side of the tube (j = 0 is the
# outer equator), spaced 4 samples apart around the centre and 3 around the tube.
WA_ANCHOR_GRID = [(i, j) for j in (WA_TORUS_M - 3, 0, 3) for i in (4, 8, 12)]
# Control points of a closed B-spline around the anchors' patch (wider than it), in loop order.
# A coarse quad layout of the whole torus for semiregular remeshing: every 9th sample around
# the centre, every 7th around the tube (8 x 4 vertices, 32 quads).
WA_QUAD_STEP = (9, 7)
WA_CURVE_GRID = [(2, 24), (8, 23), (14, 24), (16, 0), (14, 4), (8, 5), (2, 4), (0, 0)]


def wa_torus():
    V = []
    for i in range(WA_TORUS_N):
        u = 2 * math.pi * i / WA_TORUS_N
        for j in range(WA_TORUS_M):
            v = 2 * math.pi * j / WA_TORUS_M
            r = WA_TORUS_TUBE * (1 + WA_TORUS_BUMP * math.sin(3 * u) * math.cos(2 * v))
            V.append(((WA_TORUS_R + r * math.cos(v)) * math.cos(u),
                      (WA_TORUS_R + r * math.cos(v)) * math.sin(u), r * math.sin(v)))
    return V, torus_grid_triangles(WA_TORUS_N, WA_TORUS_M, other_diagonal=False)


def torus_grid_triangles(n, m, other_diagonal):
    """Two triangles per quad of an n x m periodic grid (vertex i * m + j), split along the
    (i, j)-(i+1, j+1) diagonal or the other one."""
    F = []
    for i in range(n):
        for j in range(m):
            a = i * m + j
            b = ((i + 1) % n) * m + j
            c = i * m + (j + 1) % m
            d = ((i + 1) % n) * m + (j + 1) % m
            if other_diagonal:
                F.append((a, b, c))
                F.append((b, d, c))
            else:
                F.append((a, b, d))
                F.append((a, d, c))
    return F


# The correspondence target (§4.3 of the weighted-averages paper): another torus, meshed
# differently (54 samples around the centre, triangles split along the other diagonal) and
# shaped differently (elliptical centre line, thinner tube, two bumps instead of three). Its
# anchors are its vertices at the same (u, v) as the torus's anchors (i * 54 / 72 is whole for
# i = 4, 8, 12), so the two anchor sets correspond in order.
WA_TARGET_N = 54
WA_TARGET_STRETCH = 1.3    # x scale of the centre line
WA_TARGET_TUBE = 0.33
WA_TARGET_BUMP = 0.2


def wa_torus_target():
    V = []
    for i in range(WA_TARGET_N):
        u = 2 * math.pi * i / WA_TARGET_N
        for j in range(WA_TORUS_M):
            v = 2 * math.pi * j / WA_TORUS_M
            r = WA_TARGET_TUBE * (1 + WA_TARGET_BUMP * math.sin(2 * u) * math.cos(v))
            V.append((WA_TARGET_STRETCH * (WA_TORUS_R + r * math.cos(v)) * math.cos(u),
                      (WA_TORUS_R + r * math.cos(v)) * math.sin(u), r * math.sin(v)))
    return V, torus_grid_triangles(WA_TARGET_N, WA_TORUS_M, other_diagonal=True)


def wa_weights_text():
    """Rows of weights for the 9 anchors (row-major 3 x 3 patch): the centre, the patch's
    centroid, bilinear samples along its diagonal and one affine (extrapolating) row."""
    rows = [[0, 0, 0, 0, 1, 0, 0, 0, 0], [1 / 9.0] * 9]
    for k in range(1, 8):
        t = k / 8.0
        # bilinear weights of (t, t) on the 3 x 3 grid of nodes 0, 1/2, 1
        def hat(x, node):
            return max(0.0, 1 - abs(x - node) * 2)
        w = [hat(t, a / 2.0) * hat(t, b / 2.0) for b in range(3) for a in range(3)]
        rows.append(w)
    rows.append([0, 0, 0, -0.1, 0.6, 0.5, 0, 0, 0])
    for w in rows:
        assert abs(sum(w) - 1) < 1e-12
    return "".join(" ".join(repr(float(x)) for x in w) + "\n" for w in rows)


# C1 spline deformations (2.5D, Rodrigues et al. 2014, section 5) ----------------------------
# A nematode-like organism (C. elegans style: a slender, slightly flattened tube with rounded
# ends, tail at -x thinner than the head at +x) lying straight along the x axis; the 2D domain
# of the spline (a regular triangulation of a rectangle around it, the base of the single layer
# of prisms); and a "microscope picture" of the same organism seen from above but bent, the
# target a user deforms the model towards. The bend is the plane map
# (x, y) -> (x, y + SPLINE_BEND_AMPLITUDE * sin(pi * x)), the analytic reference for tests.
SPLINE_HALF_LENGTH = 0.8       # organism: x in [-0.8, 0.8] (pole vertices at the ends)
SPLINE_HALF_WIDTH = 0.085      # W: y half-width scale (the widest point is 1.011 W)
SPLINE_FLATTEN = 0.7           # z half-thickness / y half-width, at every cross-section
SPLINE_TAPER = (0.12, -0.30)   # g(s) = 1 + 0.12 s - 0.30 s^2: tail (s = -1) 0.58, head 0.82
SPLINE_RINGS = 100             # rings along x (+2 poles) -> 24 * 100 + 2 = 2402 vertices
SPLINE_RING_SIZE = 24          # vertices per ring -> 2 * 24 * 100 = 4800 triangles
SPLINE_DOMAIN = (-1.0, 1.0, -0.5, 0.5)   # x0, x1, y0, y1 of the spline's 2D domain
SPLINE_DOMAIN_STEP = 0.125     # grid spacing (dyadic: every coordinate exact in binary)
SPLINE_MIN_CLEARANCE = 0.05    # asserted: organism (straight and bent) this far inside
SPLINE_BEND_AMPLITUDE = 0.18   # the picture's centre line: y = 0.18 sin(pi x)
SPLINE_PICTURE_SIZE = (512, 256)   # pixels (width, height): 256 pixels per unit


def spline_taper(s):
    """g(s): the profile's taper, s = x / half-length (tail -1, head +1)."""
    return 1.0 + SPLINE_TAPER[0] * s + SPLINE_TAPER[1] * s * s


def spline_profile(x):
    """Half-width (along y) of the straight organism's cross-section at x; 0 at and beyond
    the ends. W sqrt(1 - s^4) g(s), s = x / half-length: flat along the body, rounded ends."""
    s = x / SPLINE_HALF_LENGTH
    if abs(s) >= 1.0:
        return 0.0
    return SPLINE_HALF_WIDTH * math.sqrt(1.0 - s ** 4) * spline_taper(s)


def spline_bend(x):
    """The picture's centre line: y = A sin(pi x)."""
    return SPLINE_BEND_AMPLITUDE * math.sin(math.pi * x)


def spline_organism():
    """Ring-and-pole tube (ring_tube on the ellipsoid with half-axes (a, 1, 1)), each
    cross-section rescaled to the profile: a ring vertex at x = -a cos t has radius sin t =
    sqrt(1 - s^2), so y is scaled by W sqrt(1 + s^2) g(s) (giving W sqrt(1 - s^4) g(s)) and z by
    SPLINE_FLATTEN times that. A positive scale per x-slice: injective, still outward."""
    a = SPLINE_HALF_LENGTH
    S, F = ring_tube(SPLINE_RINGS, SPLINE_RING_SIZE, (a, 1.0, 1.0))
    V = []
    for x, y, z in S:
        s = x / a
        k = SPLINE_HALF_WIDTH * math.sqrt(1.0 + s * s) * spline_taper(s)
        V.append((rnd(x), rnd(k * y), rnd(SPLINE_FLATTEN * k * z)))
    return V, F


def spline_domain():
    """A regular triangulation of the domain rectangle: squares of side SPLINE_DOMAIN_STEP,
    vertex j * (ni + 1) + i at (x0 + i step, y0 + j step) (row by row, bottom to top). Square
    (i, j) is cut along its lower-left/upper-right diagonal when (i // 2 + j) is even, along the
    other one otherwise: interior vertices of degrees 4, 6 and 8. Counter-clockwise."""
    x0, x1, y0, y1 = SPLINE_DOMAIN
    h = SPLINE_DOMAIN_STEP
    ni, nj = int(round((x1 - x0) / h)), int(round((y1 - y0) / h))
    V = [(x0 + i * h, y0 + j * h) for j in range(nj + 1) for i in range(ni + 1)]
    F = []
    for j in range(nj):
        for i in range(ni):
            a = j * (ni + 1) + i
            b, c, d = a + 1, a + ni + 1, a + ni + 2
            if (i // 2 + j) % 2 == 0:
                F += [(a, b, d), (a, d, c)]
            else:
                F += [(a, b, c), (b, d, c)]
    return V, F, (ni, nj)


def check_spline_domain(V, F, shape):
    """Counter-clockwise, consistently oriented disk covering the rectangle exactly; returns
    the degree histogram of the interior vertices."""
    ni, nj = shape
    x0, x1, y0, y1 = SPLINE_DOMAIN
    assert len(V) == (ni + 1) * (nj + 1) and len(F) == 2 * ni * nj
    for x, y in V:
        assert x == rnd(x) and y == rnd(y), "spline_domain: vertex not exact in 6 decimals"
        assert x * 8 == int(x * 8) and y * 8 == int(y * 8), "spline_domain: vertex not dyadic"
    directed = set()
    for t in F:
        assert cross2(V[t[0]], V[t[1]], V[t[2]]) > 0, "spline_domain: triangle %s not CCW" % (t,)
        for e in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            assert e not in directed, "spline_domain: directed edge %s twice" % (e,)
            directed.add(e)
    assert len({v for t in F for v in t}) == len(V), "spline_domain: unreferenced vertices"
    n_edges = len({(min(e), max(e)) for e in directed})
    assert len(V) - n_edges + len(F) == 1, "spline_domain: not a disk"
    area = sum(0.5 * cross2(V[a], V[b], V[c]) for a, b, c in F)
    assert area == (x1 - x0) * (y1 - y0), "spline_domain: area %r" % area
    neighbours = {}
    for a, b in directed:
        neighbours.setdefault(a, set()).add(b)
        neighbours.setdefault(b, set()).add(a)
    hist = {}
    for v, (x, y) in enumerate(V):
        if x0 < x < x1 and y0 < y < y1:
            d = len(neighbours[v])
            hist[d] = hist.get(d, 0) + 1
    assert sorted(hist) == [4, 6, 8], "spline_domain: interior degrees %s" % hist
    return hist


def check_spline_organism(V, F):
    """Closed outward manifold sphere without self-intersections, flattened as asked, inside
    the domain with the clearance, straight and bent."""
    assert 3000 <= len(F) <= 6000, "spline_organism: %d triangles" % len(F)
    vol = check_closed_surface(V, F, "spline_organism")
    tested = check_no_self_intersections(V, F, "spline_organism")
    x0, x1, y0, y1 = SPLINE_DOMAIN
    box = [(min(v[k] for v in V), max(v[k] for v in V)) for k in range(3)]
    clear = min(box[0][0] - x0, x1 - box[0][1], box[1][0] - y0, y1 - box[1][1])
    assert clear >= SPLINE_MIN_CLEARANCE, "spline_organism: clearance %.4f to the domain" % clear
    bent = [y + spline_bend(x) for x, y, _ in V]
    bent_clear = min(min(bent) - y0, y1 - max(bent))     # the bend keeps x
    assert bent_clear >= SPLINE_MIN_CLEARANCE, "spline_organism: bent, y clearance %.4f" % bent_clear
    ratio = box[2][1] / box[1][1]
    assert abs(ratio - SPLINE_FLATTEN) < 0.01, "spline_organism: z / y half-extent %.4f" % ratio
    assert abs(box[0][0] + SPLINE_HALF_LENGTH) < 1e-9 and abs(box[0][1] - SPLINE_HALF_LENGTH) < 1e-9
    # The straight organism's vertices lie within the analytic profile (the picture's outline).
    for x, y, z in V:
        r = spline_profile(x)
        assert abs(y) <= r + 1e-6 and abs(z) <= SPLINE_FLATTEN * r + 1e-6
    return {"volume": vol, "tested": tested, "bbox": box, "clearance": clear,
            "bent_clearance": bent_clear}


def spline_outline(samples=600):
    """The bent organism's silhouette as a closed polygon (counter-clockwise): the upper side
    (x, b(x) + r(x)) from tail to head at x = -a cos(pi k / samples), then the lower side back."""
    a = SPLINE_HALF_LENGTH
    xs = [-a * math.cos(math.pi * k / samples) for k in range(samples + 1)]
    lower = [(x, spline_bend(x) - spline_profile(x)) for x in xs]
    upper = [(x, spline_bend(x) + spline_profile(x)) for x in xs]
    return lower + list(reversed(upper[1:-1]))


def spline_picture():
    """A greyscale 'microscope picture' of the organism seen from above, bent: pixel (i, j)
    (column i, row j from the top) is sampled at x = -1 + (i + 0.5) / 256, y = 0.5 - (j + 0.5) /
    256, so the picture covers the domain rectangle exactly. A point is inside the organism when
    |y - b(x)| < r(x) (b = spline_bend, r = spline_profile: the straight model's top-view
    silhouette moved by (x, y) -> (x, y + b(x))). Bright background with vignetting, a soft
    dark outline (Gaussian in the distance to the silhouette), a lighter interior, darker where
    the body is thicker, a darker gut along the centre line and a pharynx bulb near the head.
    Returns (png bytes, rows, stats)."""
    width, height = SPLINE_PICTURE_SIZE
    x0, x1, y0, y1 = SPLINE_DOMAIN
    px = (x1 - x0) / width
    assert abs((y1 - y0) / height - px) < 1e-15, "spline picture: pixels not square"
    a = SPLINE_HALF_LENGTH
    # Silhouette segments binned in square cells of 8 pixels, for the distance to the outline.
    poly = spline_outline()
    cell = 8 * px
    bins = {}

    def cells(u, v):
        return range(int(math.floor(min(u, v) / cell)), int(math.floor(max(u, v) / cell)) + 1)
    for k in range(len(poly)):
        p, q = poly[k], poly[(k + 1) % len(poly)]
        for ci in cells(p[0], q[0]):
            for cj in cells(p[1], q[1]):
                bins.setdefault((ci, cj), []).append((p, q))
    sigma = 1.5 * px            # outline width
    rows = []
    darkest, darkest_d = 255, None
    for j in range(height):
        y = y1 - (j + 0.5) * px
        row = []
        for i in range(width):
            x = x0 + (i + 0.5) * px
            vignette = 1.0 - 0.18 * 0.5 * (x * x + (2.0 * y) ** 2)
            r = spline_profile(x)
            yc = y - spline_bend(x)
            inside = abs(yc) < r
            ci, cj = int(math.floor(x / cell)), int(math.floor(y / cell))
            segs = [sg for di in (-1, 0, 1) for dj in (-1, 0, 1)
                    for sg in bins.get((ci + di, cj + dj), ())]
            d = min(dist_point_segment2((x, y), p, q) for p, q in segs) if segs else cell
            d = d if inside else -d         # signed distance, positive inside
            background = 238.0
            if inside:
                q = yc / r
                thick = math.sqrt(1.0 - q * q)
                s = x / a
                body = 214.0 - 30.0 * thick
                gut = smoothstep((s + 0.85) / 0.2) * smoothstep((0.8 - s) / 0.2)   # fades at the ends
                body -= 34.0 * math.exp(-(q / 0.22) ** 2) * gut
                bulb = ((x - 0.5) / 0.045) ** 2 + (yc / (0.45 * SPLINE_HALF_WIDTH)) ** 2   # pharynx
                body -= 28.0 * math.exp(-bulb)
            else:
                body = background
            cover = smoothstep(0.5 + d / px)      # anti-aliased edge, one pixel wide
            value = cover * body + (1.0 - cover) * background
            value -= 125.0 * math.exp(-((d - 0.5 * px) / sigma) ** 2)
            value = int(round(min(255.0, max(0.0, value * vignette))))
            if value < darkest:
                darkest, darkest_d = value, d
            row.append(value)
        rows.append(row)
    stats = {"darkest": darkest, "darkest_distance": darkest_d, "outline_points": len(poly)}
    return png_bytes(width, height, rows, channels=1), rows, stats


def check_spline_picture(rows, stats):
    """The picture shows the bent organism: the bent centre line is inside (interior grey), the
    straight one is background there, the darkest pixels are on the outline, the corners are
    darker than the middle of the background (vignetting)."""
    width, height = SPLINE_PICTURE_SIZE
    x0, _, _, y1 = SPLINE_DOMAIN
    px = 1.0 / 256

    def pixel(x, y):
        return rows[int(math.floor((y1 - y) / px))][int(math.floor((x - x0) / px))]
    assert len(rows) == height and all(len(r) == width for r in rows)
    for x in (-0.5, 0.0, 0.25, 0.5):
        inner = pixel(x, spline_bend(x))
        assert 90 < inner < 215, "spline picture: centre line at x = %g is %d" % (x, inner)
    for x in (-0.5, 0.5):
        assert pixel(x, 0.0) > 225, "spline picture: the straight centre line is not background"
    assert stats["darkest"] < 110 and abs(stats["darkest_distance"]) < 2 * px, \
        "spline picture: the darkest pixel is not on the outline"
    corners = [rows[0][0], rows[0][-1], rows[-1][0], rows[-1][-1]]
    assert max(corners) < pixel(0.0, 0.45) - 20, "spline picture: no vignetting"
    return corners


# ---------------------------------------------------------------------------
# Organ workflow (issue 15): a liver-like label map (NIfTI-1) and landmarks (3D Slicer markups)
# ---------------------------------------------------------------------------
# Physical space: LPS millimetres (x to the patient's left, y posterior, z superior), as ITK and
# 3D Slicer's markups files use it. The NIfTI header stores the same grid in RAS, as NIfTI
# requires (qform = sform = diag(-sx, -sy, sz) with the origin's x and y negated).

def organ_fields(u, v, w):
    """The organ's implicit function at local LPS offsets (u, v, w) mm from ORGAN_CENTRE:
    negative inside, about a signed distance in mm near the surface. A smooth union of four
    ellipsoids (right lobe, inferior tip of the right lobe, left lobe, caudate), minus a smooth
    notch on the visceral (inferior, posterior, medial) side, with a gentle lobulation."""
    k = ORGAN_BLEND_MM
    total = 0.0
    for (cu, cv, cw), (ru, rv, rw) in ORGAN_LOBES:
        du, dv, dw = (u - cu) / ru, (v - cv) / rv, (w - cw) / rw
        d = (math.sqrt(du * du + dv * dv + dw * dw) - 1.0) * min(ru, rv, rw)
        total += math.exp(-d / k)
    f = -k * math.log(total) if total > 0.0 else 1e9
    (cu, cv, cw), (ru, rv, rw) = ORGAN_NOTCH
    du, dv, dw = (u - cu) / ru, (v - cv) / rv, (w - cw) / rw
    g = (math.sqrt(du * du + dv * dv + dw * dw) - 1.0) * min(ru, rv, rw)
    # smooth max(f, -g): outside the notch
    a, b = f / k, -g / k
    m = max(a, b)
    f = k * (m + math.log(math.exp(a - m) + math.exp(b - m)))
    f += ORGAN_LOBULATION_MM * math.sin(u / 17.0) * math.sin(v / 13.0 + 0.5) * math.cos(w / 19.0)
    return f


def lesion_field(u, v, w):
    (cu, cv, cw), (ru, rv, rw) = ORGAN_LESION
    du, dv, dw = (u - cu) / ru, (v - cv) / rv, (w - cw) / rw
    return (math.sqrt(du * du + dv * dv + dw * dw) - 1.0) * min(ru, rv, rw)


def organ_voxel_centre(i, j, k):
    """LPS position of voxel (i, j, k): origin + index * spacing (identity direction)."""
    return tuple(ORGAN_ORIGIN[a] + (i, j, k)[a] * ORGAN_SPACING[a] for a in range(3))


def organ_label_map():
    """Labels in NIfTI order (i fastest): 1 organ, 2 lesion (inside the organ), 0 background;
    also the organ's minimum field value over the lesion's voxels."""
    nx, ny, nz = ORGAN_DIMS
    cx, cy, cz = ORGAN_CENTRE
    labels = bytearray(nx * ny * nz)
    deepest_lesion = -1e9  # the largest (least deep) organ field value on a lesion voxel
    reach = 0.0  # the largest distance of an organ voxel from ORGAN_CENTRE
    xs = [ORGAN_ORIGIN[0] + i * ORGAN_SPACING[0] - cx for i in range(nx)]
    for k in range(nz):
        w = ORGAN_ORIGIN[2] + k * ORGAN_SPACING[2] - cz
        for j in range(ny):
            v = ORGAN_ORIGIN[1] + j * ORGAN_SPACING[1] - cy
            row = (k * ny + j) * nx
            for i, u in enumerate(xs):
                # quick rejection: far outside every lobe's bounding sphere
                if u * u + v * v + w * w > ORGAN_BOUND_MM ** 2:
                    continue
                f = organ_fields(u, v, w)
                if f <= 0.0:
                    reach = max(reach, u * u + v * v + w * w)
                    if lesion_field(u, v, w) <= 0.0:
                        labels[row + i] = 2
                        deepest_lesion = max(deepest_lesion, f)
                    else:
                        labels[row + i] = 1
    # the quick rejection cut nothing off: the organ ends well inside the bounding sphere
    assert math.sqrt(reach) <= ORGAN_BOUND_MM - 10.0, "organ_label: reaches %.1f mm" % math.sqrt(reach)
    return labels, deepest_lesion


def components6(labels, dims, member):
    """Number of 6-connected components of the voxels whose label satisfies member(label), and
    the size of the largest."""
    nx, ny, nz = dims
    seen = bytearray(len(labels))
    count, largest = 0, 0
    for start in range(len(labels)):
        if seen[start] or not member(labels[start]):
            continue
        count += 1
        size = 0
        seen[start] = 1
        stack = [start]
        while stack:
            n = stack.pop()
            size += 1
            i = n % nx
            j = (n // nx) % ny
            k = n // (nx * ny)
            for m, ok in ((n - 1, i > 0), (n + 1, i < nx - 1), (n - nx, j > 0),
                          (n + nx, j < ny - 1), (n - nx * ny, k > 0), (n + nx * ny, k < nz - 1)):
                if ok and not seen[m] and member(labels[m]):
                    seen[m] = 1
                    stack.append(m)
        largest = max(largest, size)
    return count, largest


def check_organ_label_map(labels, deepest_lesion):
    """The label map is what the workflow needs: one organ (labels 1 and 2 together one
    6-connected component, the background one component: no cavity, so a closed surface), one
    lesion strictly inside it (every lesion voxel at least ORGAN_LESION_DEPTH_MM deep), no label
    within ORGAN_BORDER_VOXELS of the image border, about the size of a liver, and not an
    ellipsoid (the ellipsoid of the same second moments differs by at least 10% of the volume)."""
    nx, ny, nz = ORGAN_DIMS
    voxel = ORGAN_SPACING[0] * ORGAN_SPACING[1] * ORGAN_SPACING[2]
    organ = [n for n in range(len(labels)) if labels[n]]
    lesion = sum(1 for n in organ if labels[n] == 2)
    volume = len(organ) * voxel / 1000.0  # mL
    assert 700.0 <= volume <= 2200.0, "organ_label: volume %.1f mL is not liver-like" % volume
    assert 1500 <= lesion * voxel <= 12000, "organ_label: lesion of %.0f mm^3" % (lesion * voxel)
    b = ORGAN_BORDER_VOXELS
    for n in organ:
        i, j, k = n % nx, (n // nx) % ny, n // (nx * ny)
        assert b <= i < nx - b and b <= j < ny - b and b <= k < nz - b, \
            "organ_label: voxel (%d, %d, %d) within %d voxels of the border" % (i, j, k, b)
    assert components6(labels, ORGAN_DIMS, lambda l: l != 0) == (1, len(organ)), \
        "organ_label: the organ is not one 6-connected component"
    assert components6(labels, ORGAN_DIMS, lambda l: l == 0)[0] == 1, \
        "organ_label: the background is not connected (the organ has a cavity)"
    assert components6(labels, ORGAN_DIMS, lambda l: l == 2) == (1, lesion), \
        "organ_label: the lesion is not one component"
    assert deepest_lesion <= -ORGAN_LESION_DEPTH_MM, \
        "organ_label: a lesion voxel is only %.2f mm inside the organ" % -deepest_lesion
    # the ellipsoid with the organ's second moments
    pts = [organ_voxel_centre(n % nx, (n // nx) % ny, n // (nx * ny)) for n in organ]
    mean = [sum(p[a] for p in pts) / len(pts) for a in range(3)]
    cov = [[sum((p[a] - mean[a]) * (p[c] - mean[c]) for p in pts) / len(pts) for c in range(3)]
           for a in range(3)]
    inv = invert3(cov)
    # a solid ellipsoid (x-m)^T S^-1 (x-m) <= 5 has covariance S
    inside_ellipsoid = 0
    differ = 0
    organ_set = bytearray(len(labels))
    for n in organ:
        organ_set[n] = 1
    for n in range(len(labels)):
        i, j, k = n % nx, (n // nx) % ny, n // (nx * ny)
        p = organ_voxel_centre(i, j, k)
        d = [p[a] - mean[a] for a in range(3)]
        q = sum(d[a] * inv[a][c] * d[c] for a in range(3) for c in range(3))
        e = q <= 5.0
        inside_ellipsoid += e
        differ += e != bool(organ_set[n])
    mismatch = differ / len(organ)
    assert mismatch >= 0.10, "organ_label: within %.1f%% of an ellipsoid" % (100 * mismatch)
    bbox = [(min(p[a] for p in pts), max(p[a] for p in pts)) for a in range(3)]
    return {"volume": volume, "lesion": lesion * voxel / 1000.0, "voxels": len(organ),
            "mismatch": mismatch, "bbox": bbox}


def invert3(m):
    a, b, c = m
    det = (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
           + a[2] * (b[0] * c[1] - b[1] * c[0]))
    assert abs(det) > 1e-12
    cof = [[b[1] * c[2] - b[2] * c[1], a[2] * c[1] - a[1] * c[2], a[1] * b[2] - a[2] * b[1]],
           [b[2] * c[0] - b[0] * c[2], a[0] * c[2] - a[2] * c[0], a[2] * b[0] - a[0] * b[2]],
           [b[0] * c[1] - b[1] * c[0], a[1] * c[0] - a[0] * c[1], a[0] * b[1] - a[1] * b[0]]]
    return [[cof[r][s] / det for s in range(3)] for r in range(3)]


def nifti1_label_map(labels):
    """A NIfTI-1 single file (.nii) of unsigned 8-bit labels: 348-byte header, 4 bytes of no
    extension, the voxels (i fastest). The grid is stored in RAS as NIfTI requires: sform and
    qform (both code 1, scanner) map (i, j, k) to (-x, -y, z) of the LPS position
    origin + index * spacing (identity LPS direction: a standard axial grid)."""
    import struct
    nx, ny, nz = ORGAN_DIMS
    sx, sy, sz = ORGAN_SPACING
    ox, oy, oz = ORGAN_ORIGIN
    header = struct.pack(
        "<i10s18sihcc8h3fhhhh8ffffhcc4f2i80s24shh6f4f4f4f16s4s",
        348, b"", b"", 0, 0, b"r", b"\0",
        3, nx, ny, nz, 1, 1, 1, 1,       # dim
        0.0, 0.0, 0.0,                   # intent_p1..3
        1002,                            # intent_code: NIFTI_INTENT_LABEL
        2, 8,                            # datatype UINT8, bitpix
        0,                               # slice_start
        1.0, sx, sy, sz, 0.0, 0.0, 0.0, 0.0,  # pixdim (pixdim[0] = qfac = 1)
        352.0,                           # vox_offset
        1.0, 0.0,                        # scl_slope, scl_inter
        0, b"\0", b"\x02",               # slice_end, slice_code, xyzt_units: mm
        2.0, 0.0, 0.0, 0.0,              # cal_max, cal_min, slice_duration, toffset
        2, 0,                            # glmax, glmin
        ORGAN_DESCRIPTION.encode("ascii"), b"",
        1, 1,                            # qform_code, sform_code: scanner
        0.0, 0.0, 1.0,                   # quatern_b, c, d: 180 degrees about z (LPS -> RAS)
        -ox, -oy, oz,                    # qoffset_x, y, z (RAS)
        -sx, 0.0, 0.0, -ox,              # srow_x
        0.0, -sy, 0.0, -oy,              # srow_y
        0.0, 0.0, sz, oz,                # srow_z
        b"", b"n+1\0")
    assert len(header) == 348
    return header + b"\0\0\0\0" + bytes(labels)


def check_nifti1(data, labels):
    """Reads the header back (independently of how it was packed: by offset, as NIfTI-1
    defines them) and checks the grid it states."""
    import struct
    assert struct.unpack_from("<i", data, 0)[0] == 348 and data[344:348] == b"n+1\0"
    dim = struct.unpack_from("<8h", data, 40)
    assert dim[:4] == (3,) + tuple(ORGAN_DIMS), dim
    assert struct.unpack_from("<hh", data, 70) == (2, 8)
    pixdim = struct.unpack_from("<8f", data, 76)
    assert pixdim[0] == 1.0 and pixdim[1:4] == tuple(ORGAN_SPACING)
    assert struct.unpack_from("<f", data, 108)[0] == 352.0
    assert struct.unpack_from("<hh", data, 252) == (1, 1)
    srow = [struct.unpack_from("<4f", data, 280 + 16 * r) for r in range(3)]
    # voxel (i, j, k) -> RAS by the sform; negate x, y -> LPS; compare with the LPS grid
    for i, j, k in ((0, 0, 0), (ORGAN_DIMS[0] - 1, 3, 7), (5, ORGAN_DIMS[1] - 1, ORGAN_DIMS[2] - 1)):
        ras = [srow[r][0] * i + srow[r][1] * j + srow[r][2] * k + srow[r][3] for r in range(3)]
        lps = (-ras[0], -ras[1], ras[2])
        expected = organ_voxel_centre(i, j, k)
        assert all(abs(lps[a] - expected[a]) < 1e-9 for a in range(3)), (lps, expected)
    qb, qc, qd, qx, qy, qz = struct.unpack_from("<6f", data, 256)
    assert (qb, qc, qd) == (0.0, 0.0, 1.0) and (qx, qy, qz) == (srow[0][3], srow[1][3], srow[2][3])
    assert data[352:] == bytes(labels)


def organ_surface_point(direction, start):
    """Where the ray from @p start (local mm, inside) along @p direction leaves the organ:
    marching in 0.5 mm steps, then bisection to 1e-9 mm."""
    n = math.sqrt(sum(d * d for d in direction))
    d = [c / n for c in direction]
    at = lambda t: organ_fields(*(start[a] + t * d[a] for a in range(3)))
    assert at(0.0) < 0.0
    t = 0.0
    while at(t + 0.5) < 0.0:
        t += 0.5
        assert t < 200.0
    lo, hi = t, t + 0.5
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        if at(mid) < 0.0:
            lo = mid
        else:
            hi = mid
    return tuple(start[a] + lo * d[a] for a in range(3))


def organ_landmarks(bbox):
    """(label, description, LPS point) of each landmark, superior first: eight around the organ,
    at the corners of its bounding box (of voxel centres, @p bbox) grown by
    ORGAN_AROUND_MARGIN_MM, where landmarks on the surrounding anatomy (diaphragm, ribs, spine,
    abdominal wall) would be, so that their convex hull holds the whole organ (celestial
    coordinates are defined inside the hull); the dome, where the ray from ORGAN_RAY_START along
    ORGAN_DOME_RAY leaves the organ's surface; and the lesion's centre."""
    cx, cy, cz = ORGAN_CENTRE
    mx, my, mz = ORGAN_AROUND_MARGIN_MM
    out = []
    for z, zname in ((bbox[2][1] + mz, "superior"), (bbox[2][0] - mz, "inferior")):
        for x, xname in ((bbox[0][0] - mx, "right"), (bbox[0][1] + mx, "left")):
            for y, yname in ((bbox[1][0] - my, "anterior"), (bbox[1][1] + my, "posterior")):
                out.append(("%s-%s-%s" % (zname, xname, yname),
                            "around the organ: %s %s %s corner of its bounding box grown by %g %g %g mm"
                            % (zname, xname, yname, mx, my, mz), (rnd(x), rnd(y), rnd(z))))
    p = organ_surface_point(ORGAN_DOME_RAY, ORGAN_RAY_START)
    out.append(("dome", "superior dome of the right lobe (on the surface)",
                (rnd(p[0] + cx), rnd(p[1] + cy), rnd(p[2] + cz))))
    (lu, lv, lw), _ = ORGAN_LESION
    out.append(("lesion", "centre of the lesion (label 2)", (rnd(lu + cx), rnd(lv + cy), rnd(lw + cz))))
    return out


def breathing_motion(p, zmin, zmax):
    """Inspiration: the diaphragm pushes the liver caudally (-z), more at the dome than at the
    inferior tip (compression along z), and slightly anteriorly (-y)."""
    t = (p[2] - zmin) / (zmax - zmin)
    return (rnd(p[0]), rnd(p[1] - ORGAN_BREATH_ANTERIOR_MM * t),
            rnd(p[2] - ORGAN_BREATH_SHIFT_MM[0] - (ORGAN_BREATH_SHIFT_MM[1] - ORGAN_BREATH_SHIFT_MM[0]) * t))


def check_organ_landmarks(marks, labels, moved):
    """The dome lies on the organ's surface (|field| < 1e-5 mm at the written, rounded point,
    and the voxels around it hold both the organ and the background); the lesion landmark is in
    a lesion voxel; the others are outside the organ, and every organ voxel centre lies inside
    the landmarks' convex hull, at least 5 mm from its faces; every landmark and moved landmark
    lies inside the image; the motion moves each landmark caudally by the stated amounts.
    Returns the dome's distance to the surface and the hull's margin."""
    nx, ny, nz = ORGAN_DIMS
    cx, cy, cz = ORGAN_CENTRE
    lo = ORGAN_ORIGIN
    hi = tuple(ORGAN_ORIGIN[a] + ((nx, ny, nz)[a] - 1) * ORGAN_SPACING[a] for a in range(3))
    assert 6 <= len(marks) <= 10
    assert len({m[0] for m in marks}) == len(marks), "organ landmarks: labels repeat"
    assert not any(set(',"\\') & set(m[0] + m[1]) for m in marks), "organ landmarks: quote a label"
    surface = None
    for label, _, p in marks:
        index = [int(round((p[a] - ORGAN_ORIGIN[a]) / ORGAN_SPACING[a])) for a in range(3)]
        voxel = lambda i, j, k: labels[(k * ny + j) * nx + i]
        f = organ_fields(p[0] - cx, p[1] - cy, p[2] - cz)
        if label == "lesion":
            assert voxel(*index) == 2, "organ landmarks: the lesion landmark is not in the lesion"
        elif label == "dome":
            surface = abs(f)
            assert abs(f) < 1e-5, "organ landmarks: %s is %.2e mm off the surface" % (label, f)
            around = {voxel(index[0] + a, index[1] + b, index[2] + c)
                      for a in (-1, 0, 1) for b in (-1, 0, 1) for c in (-1, 0, 1)}
            assert 0 in around and (1 in around or 2 in around), \
                "organ landmarks: %s is not on the label map's boundary" % label
        else:
            assert f > 0.0, "organ landmarks: %s is inside the organ" % label
    assert surface is not None
    organ = [organ_voxel_centre(n % nx, (n // nx) % ny, n // (nx * ny))
             for n in range(len(labels)) if labels[n]]
    margin = check_inside_hull(organ, [p for _, _, p in marks], "organ_landmarks")
    assert margin >= 5.0, "organ landmarks: an organ voxel is %.2f mm from their hull" % margin
    for q in [m[2] for m in marks] + moved:
        assert all(lo[a] <= q[a] <= hi[a] for a in range(3)), "organ landmarks: %s outside the image" % (q,)
    for (_, _, p), q in zip(marks, moved):
        dz = p[2] - q[2]
        assert ORGAN_BREATH_SHIFT_MM[0] - 1e-6 <= dz <= ORGAN_BREATH_SHIFT_MM[1] + 1e-6, dz
    return surface, margin


def markups_json(marks):
    """3D Slicer markups JSON (schema v1.0.3, as Slicer 5 writes it), a point list in LPS."""
    lines = ['{',
             '    "@schema": "https://raw.githubusercontent.com/slicer/slicer/master/Modules/'
             'Loadable/Markups/Resources/Schema/markups-schema-v1.0.3.json#",',
             '    "markups": [',
             '        {',
             '            "type": "Fiducial",',
             '            "coordinateSystem": "LPS",',
             '            "coordinateUnits": "mm",',
             '            "locked": false,',
             '            "fixedNumberOfControlPoints": false,',
             '            "labelFormat": "%N-%d",',
             '            "lastUsedControlPointNumber": %d,' % len(marks),
             '            "controlPoints": [']
    for n, (label, desc, p) in enumerate(marks):
        lines += ['                {',
                  '                    "id": "%d",' % (n + 1),
                  '                    "label": "%s",' % label,
                  '                    "description": "%s",' % desc,
                  '                    "associatedNodeID": "",',
                  '                    "position": [%s, %s, %s],' % tuple(fmt(x) for x in p),
                  '                    "orientation": [-1.0, -0.0, -0.0, -0.0, -1.0, -0.0, 0.0, 0.0, 1.0],',
                  '                    "selected": true,',
                  '                    "locked": false,',
                  '                    "visibility": true,',
                  '                    "positionStatus": "defined"',
                  '                }' + (',' if n + 1 < len(marks) else '')]
    lines += ['            ],', '            "measurements": []', '        }', '    ]', '}']
    return "\n".join(lines) + "\n"


def markups_fcsv_ras(marks):
    """The same points as a legacy 3D Slicer .fcsv in RAS (x and y negated)."""
    out = ["# Markups fiducial file version = 4.11", "# CoordinateSystem = RAS",
           "# columns = id,x,y,z,ow,ox,oy,oz,vis,sel,lock,label,desc,associatedNodeID"]
    for n, (label, desc, p) in enumerate(marks):
        out.append("%d,%s,%s,%s,0,0,0,1,1,1,0,%s,%s," % (n + 1, fmt(-p[0]), fmt(-p[1]), fmt(p[2]), label, desc))
    return "\n".join(out) + "\n"


def check_markups_files(json_text, fcsv_text, marks):
    """The written files hold the landmarks: the JSON parses (json module) to the LPS points,
    the .fcsv's RAS rows negate back to the same points."""
    import json
    doc = json.loads(json_text)
    cps = doc["markups"][0]["controlPoints"]
    assert doc["markups"][0]["coordinateSystem"] == "LPS" and len(cps) == len(marks)
    for cp, (label, _, p) in zip(cps, marks):
        assert cp["label"] == label and tuple(cp["position"]) == p, (cp, p)
    rows = [r for r in fcsv_text.splitlines() if not r.startswith("#")]
    assert len(rows) == len(marks)
    for r, (label, _, p) in zip(rows, marks):
        f = r.split(",")
        assert f[11] == label and (-float(f[1]), -float(f[2]), float(f[3])) == p, (r, p)


def main(argv):
    out_dir = argv[1] if len(argv) > 1 else os.path.dirname(os.path.abspath(__file__))
    files = {}
    summary = []

    # 2D ----------------------------------------------------------------------
    cage2d = gingerbread_cage()
    check_simple_ccw_polygon(cage2d, "cage2d")
    posed2d = gingerbread_posed(cage2d)
    check_simple_ccw_polygon(posed2d, "cage2d_posed")
    assert len(posed2d) == len(cage2d)
    model2d_V, model2d_F = triangulated_interior(cage2d, MODEL2D_SPACING, MODEL2D_MARGIN)
    stats2d = check_model2d(model2d_V, model2d_F, cage2d)
    files["cage2d.obj"] = obj_polygon_text(cage2d)
    files["cage2d_posed.obj"] = obj_polygon_text(posed2d)
    files["model2d.obj"] = obj_mesh2d_text(model2d_V, model2d_F)
    skeleton_clearance = skeleton2d_checks(cage2d)
    files["skeleton2d.tgf"] = tgf_text(SKELETON2D_JOINTS, SKELETON2D_BONES)
    files["skeleton2d_pose.txt"] = skeleton2d_pose_text()
    summary.append("skeleton2d: %d joints, %d bones, min clearance to the cage %.4f"
                   % (len(SKELETON2D_JOINTS), len(SKELETON2D_BONES), skeleton_clearance))
    summary.append("cage2d: %d vertices, area %.4f" % (len(cage2d), polygon_area(cage2d)))
    summary.append("cage2d_posed: %d vertices, area %.4f" % (len(posed2d), polygon_area(posed2d)))
    summary.append("model2d: %d vertices, %d triangles, min clearance %.4f, covers %.1f%% of "
                   "the cage" % (len(model2d_V), len(model2d_F), stats2d["min_clearance"],
                                 100.0 * stats2d["area_fraction"]))

    # 3D ----------------------------------------------------------------------
    model_V, model_F = kidney_model()
    cage_V, cage_F = kidney_cage()
    posed_V, posed_F = kidney_cage_posed()
    # Centre everything on the model's bounding box (same shift for all three).
    shift = tuple(0.5 * (min(v[k] for v in model_V) + max(v[k] for v in model_V)) for k in range(3))
    model_V, cage_V, posed_V = center_and_round([model_V, cage_V, posed_V], shift)

    assert 2000 <= len(model_V) <= 6000
    vol = check_closed_surface(model_V, model_F, "model3d")
    concave = concave_edge_count(model_V, model_F)
    assert concave > 0, "model3d is convex"
    tested_m = check_no_self_intersections(model_V, model_F, "model3d")

    assert 30 <= len(cage_V) <= 150
    cvol = check_closed_surface(cage_V, cage_F, "cage3d")
    tested_c = check_no_self_intersections(cage_V, cage_F, "cage3d")
    clearance = check_cage_encloses(model_V, cage_V, cage_F)

    assert len(posed_V) == len(cage_V) and posed_F == cage_F
    pvol = check_closed_surface(posed_V, posed_F, "cage3d_posed")
    tested_p = check_no_self_intersections(posed_V, posed_F, "cage3d_posed")

    files["model3d.off"] = off_text(model_V, model_F)
    files["cage3d.obj"] = obj_mesh3d_text(cage_V, cage_F)
    files["cage3d_posed.obj"] = obj_mesh3d_text(posed_V, posed_F)
    bbox = [(min(v[k] for v in model_V), max(v[k] for v in model_V)) for k in range(3)]
    summary.append("model3d: %d vertices, %d triangles, volume %.4f, %d concave edges, bbox %s, "
                   "%d face pairs tested" % (len(model_V), len(model_F), vol, concave,
                                             " x ".join("[%.3f, %.3f]" % b for b in bbox), tested_m))
    summary.append("cage3d: %d vertices, %d triangles, volume %.4f, min clearance to model %.4f, "
                   "%d face pairs tested" % (len(cage_V), len(cage_F), cvol, clearance, tested_c))
    summary.append("cage3d_posed: %d vertices, %d triangles, volume %.4f, %d face pairs tested"
                   % (len(posed_V), len(posed_F), pvol, tested_p))

    # Starfish (3D, ~100 controls) -------------------------------------------------------
    star_cV, star_cF = starfish_cage()
    assert 90 <= len(star_cV) <= 120
    star_cvol = check_closed_surface(star_cV, star_cF, "starfish_cage")
    tested_sc = check_no_self_intersections(star_cV, star_cF, "starfish_cage")
    star_V, star_F = starfish_model()
    star_vol = check_closed_surface(star_V, star_F, "starfish")
    tested_s = check_no_self_intersections(star_V, star_F, "starfish")
    star_clearance, tested_sm = check_starfish_encloses(star_V, star_F, star_cV, star_cF)
    files["starfish_cage.obj"] = obj_mesh3d_text(star_cV, star_cF)
    files["starfish.off"] = off_text(star_V, star_F)
    summary.append("starfish: %d vertices, %d triangles, volume %.4f, %d face pairs tested"
                   % (len(star_V), len(star_F), star_vol, tested_s))
    summary.append("starfish_cage: %d vertices, %d triangles, volume %.4f, %d face pairs tested; "
                   "min clearance to the model %.4f, %d model-cage face pairs tested"
                   % (len(star_cV), len(star_cF), star_cvol, tested_sc, star_clearance, tested_sm))

    # Organ for celestial coordinates ---------------------------------------------
    heart_V, heart_F = heart_model()
    heart_V = [tuple(rnd(v) for v in p) for p in heart_V]
    hvol = check_closed_surface(heart_V, heart_F, "heart")
    tested_h = check_no_self_intersections(heart_V, heart_F, "heart")
    controls = heart_controls()
    assert len(set(controls)) == len(controls), "heart_controls: coincident control points"
    hmargin = check_inside_hull(heart_V, controls, "heart")
    files["heart.off"] = off_text(heart_V, heart_F)
    files["heart_controls.obj"] = "".join("v %s %s %s\n" % tuple(fmt(v) for v in c) for c in controls)
    for f in range(HEART_FRAMES):
        frame = heartbeat_frame(controls, f / HEART_FRAMES)
        files["heartbeat/frame_%02d.obj" % f] = "".join(
            "v %s %s %s\n" % tuple(fmt(v) for v in c) for c in frame)
    summary.append("heart: %d vertices, %d triangles, volume %.4f, %d face pairs tested; %d controls "
                   "(14 active + 8 hull), min margin to their hull %.4f; %d heartbeat frames"
                   % (len(heart_V), len(heart_F), hvol, tested_h, len(controls), hmargin, HEART_FRAMES))

    # Weighted averages on surfaces -----------------------------------------------------
    wa_V, wa_F = wa_torus()
    wa_V = [tuple(rnd(v) for v in p) for p in wa_V]
    wvol = check_closed_surface(wa_V, wa_F, "wa_torus", genus=1)
    tested_w = check_no_self_intersections(wa_V, wa_F, "wa_torus")
    files["wa_torus.obj"] = obj_mesh3d_text(wa_V, wa_F)
    files["wa_anchors.txt"] = "".join("%s %s %s\n" % tuple(fmt(x) for x in wa_V[i * WA_TORUS_M + j])
                                      for i, j in WA_ANCHOR_GRID)
    files["wa_weights.txt"] = wa_weights_text()
    wt_V, wt_F = wa_torus_target()
    wt_V = [tuple(rnd(v) for v in p) for p in wt_V]
    wtvol = check_closed_surface(wt_V, wt_F, "wa_torus_target", genus=1)
    tested_t = check_no_self_intersections(wt_V, wt_F, "wa_torus_target")
    files["wa_torus_target.obj"] = obj_mesh3d_text(wt_V, wt_F)
    assert all(i * WA_TARGET_N % WA_TORUS_N == 0 for i, _ in WA_ANCHOR_GRID)
    files["wa_target_anchors.txt"] = "".join(
        "%s %s %s\n" % tuple(fmt(x) for x in wt_V[(i * WA_TARGET_N // WA_TORUS_N) * WA_TORUS_M + j])
        for i, j in WA_ANCHOR_GRID)
    summary.append("wa_torus_target: %d vertices, %d triangles, volume %.4f (genus 1), %d face "
                   "pairs tested" % (len(wt_V), len(wt_F), wtvol, tested_t))
    ni, nj = WA_TORUS_N // WA_QUAD_STEP[0], WA_TORUS_M // WA_QUAD_STEP[1]
    quad_v = [wa_V[(a * WA_QUAD_STEP[0]) * WA_TORUS_M + b * WA_QUAD_STEP[1]] for a in range(ni) for b in range(nj)]
    quads = [(a * nj + b, ((a + 1) % ni) * nj + b, ((a + 1) % ni) * nj + (b + 1) % nj, a * nj + (b + 1) % nj)
             for a in range(ni) for b in range(nj)]
    files["wa_quads.obj"] = ("".join("v %s %s %s\n" % tuple(fmt(x) for x in v) for v in quad_v) +
                             "".join("f %d %d %d %d\n" % tuple(k + 1 for k in q) for q in quads))
    files["wa_curve_controls.txt"] = "".join("%s %s %s\n" % tuple(fmt(x) for x in wa_V[i * WA_TORUS_M + j])
                                             for i, j in WA_CURVE_GRID)
    summary.append("wa_torus: %d vertices, %d triangles, volume %.4f (genus 1), %d face pairs "
                   "tested; %d anchors" % (len(wa_V), len(wa_F), wvol, tested_w, len(WA_ANCHOR_GRID)))

    # C1 spline deformations (2.5D) ---------------------------------------------------
    sp_V, sp_F = spline_organism()
    sp = check_spline_organism(sp_V, sp_F)
    dom_V, dom_F, dom_shape = spline_domain()
    degrees = check_spline_domain(dom_V, dom_F, dom_shape)
    files["spline_organism.obj"] = obj_mesh3d_text(sp_V, sp_F)
    files["spline_domain.obj"] = obj_mesh2d_text(dom_V, dom_F)
    summary.append("spline_organism: %d vertices, %d triangles, volume %.4f, bbox %s, clearance "
                   "to the domain %.4f (bent: y clearance %.4f), %d face pairs tested"
                   % (len(sp_V), len(sp_F), sp["volume"],
                      " x ".join("[%.3f, %.3f]" % b for b in sp["bbox"]), sp["clearance"],
                      sp["bent_clearance"], sp["tested"]))
    summary.append("spline_domain: %d vertices, %d triangles, interior vertex degrees %s"
                   % (len(dom_V), len(dom_F),
                      ", ".join("%d: %d" % kv for kv in sorted(degrees.items()))))

    # Organ workflow (issue 15): a label map and landmarks -------------------------------
    organ_labels, organ_deepest = organ_label_map()
    organ = check_organ_label_map(organ_labels, organ_deepest)
    organ_nii = nifti1_label_map(organ_labels)
    check_nifti1(organ_nii, organ_labels)
    organ_gz = gzip.compress(organ_nii, compresslevel=9, mtime=0)  # mtime 0: byte-identical runs
    assert gzip.decompress(organ_gz) == organ_nii and len(organ_gz) <= 100000
    marks = organ_landmarks(organ["bbox"])
    zs = [p[2] for _, _, p in marks]
    moved = [(label, desc, breathing_motion(p, min(zs), max(zs))) for label, desc, p in marks]
    surface_error, hull_margin = check_organ_landmarks(marks, organ_labels, [p for _, _, p in moved])
    files["organ_landmarks.mrk.json"] = markups_json(marks)
    files["organ_landmarks.fcsv"] = markups_fcsv_ras(marks)
    files["organ_landmarks_moved.mrk.json"] = markups_json(moved)
    check_markups_files(files["organ_landmarks.mrk.json"], files["organ_landmarks.fcsv"], marks)
    check_markups_files(files["organ_landmarks_moved.mrk.json"], markups_fcsv_ras(moved), moved)
    summary.append("organ_label: %s voxels of %s mm, organ %.1f mL (%d voxels), lesion %.2f mL, "
                   "bbox (LPS) %s, %.0f%% off its moment ellipsoid"
                   % (" x ".join(map(str, ORGAN_DIMS)), " x ".join(map(str, ORGAN_SPACING)),
                      organ["volume"], organ["voxels"], organ["lesion"],
                      " x ".join("[%.3f, %.3f]" % b for b in organ["bbox"]), 100 * organ["mismatch"]))
    summary.append("organ_landmarks: %d landmarks, the dome %.1e mm off the surface, the organ's "
                   "voxel centres at least %.2f mm inside their hull; moved caudally by %.0f-%.0f mm"
                   % (len(marks), surface_error, hull_margin, ORGAN_BREATH_SHIFT_MM[0],
                      ORGAN_BREATH_SHIFT_MM[1]))

    # Broken inputs -----------------------------------------------------------
    files.update(bad_files())

    spline_png, spline_rows, spline_stats = spline_picture()
    spline_corners = check_spline_picture(spline_rows, spline_stats)

    # Write (only after every check passed) --------------------------------------
    os.makedirs(os.path.join(out_dir, "bad"), exist_ok=True)
    os.makedirs(os.path.join(out_dir, "heartbeat"), exist_ok=True)
    for name in sorted(files):
        with open(os.path.join(out_dir, name), "w", encoding="ascii", newline="\n") as fh:
            fh.write(files[name])
    picture = gingerbread_picture(cage2d)
    with open(os.path.join(out_dir, "gingerbread.png"), "wb") as fh:
        fh.write(picture)
    summary.append("gingerbread.png: %d x %d pixels over cage2d's bounding box + %d%%"
                   % (IMAGE2D_SIZE, IMAGE2D_SIZE, round(100 * IMAGE2D_MARGIN)))
    with open(os.path.join(out_dir, "spline_organism_picture.png"), "wb") as fh:
        fh.write(spline_png)
    with open(os.path.join(out_dir, "organ_label.nii.gz"), "wb") as fh:
        fh.write(organ_gz)
    summary.append("organ_label.nii.gz: NIfTI-1, uint8, %d bytes gzipped (%d raw)"
                   % (len(organ_gz), len(organ_nii)))
    summary.append("spline_organism_picture.png: %d x %d greyscale pixels over the domain, "
                   "darkest %d, corners %s, %d bytes"
                   % (SPLINE_PICTURE_SIZE + (spline_stats["darkest"], spline_corners, len(spline_png))))
    for line in summary:
        print(line)
    for name in sorted(files):
        print("wrote %-28s %8d bytes" % (name, len(files[name].encode("ascii"))))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
