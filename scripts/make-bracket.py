#!/usr/bin/env python3
"""Writes data/meshes/bracket.off: the default body of the demo sweep.

An L-shaped bracket with a round hole through each leg: a base plate x in [0.5, 4],
y in [-1.5, 1.5], z in [0, 0.5] with a hole along z, an upright plate x in [0, 0.5],
z in [0.5, 4] with a hole along x, and the corner block [0, 0.5] x [-1.5, 1.5] x [0, 0.5]
joining them. Closed, 2-manifold, outward (counter-clockwise seen from outside), genus 2.

Every face is planar in a plane whose constant coordinate is exact, and every coordinate is
a float (steady reads meshes in single precision), so the file reads back unchanged. The
faces along the seams share one sampling of each edge, so there is no T-junction.

Usage: scripts/make-bracket.py [OUT.off]   (default: data/meshes/bracket.off)
"""

import math
import os
import struct
import sys

HOLE_R = 0.75
NX = 8   # segments along x of the base plate (and along z of the upright)
NY = 6   # segments along y (both plates)
Y0, Y1 = -1.5, 1.5


def f32(x):
    """x rounded to the nearest float, as a Python float."""
    return struct.unpack("f", struct.pack("f", x))[0]


def lin(a, b, n):
    return [a + (b - a) * i / n for i in range(n + 1)]


class Mesh:
    def __init__(self):
        self.v = []
        self.index = {}
        self.f = []

    def vert(self, p):
        p = tuple(f32(c) for c in p)
        if p not in self.index:
            self.index[p] = len(self.v)
            self.v.append(p)
        return self.index[p]

    def tri(self, a, b, c, out):
        """Triangle of points a, b, c turned so that its normal has a positive dot with out."""
        ia, ib, ic = self.vert(a), self.vert(b), self.vert(c)
        pa, pb, pc = self.v[ia], self.v[ib], self.v[ic]
        u = [pb[k] - pa[k] for k in range(3)]
        w = [pc[k] - pa[k] for k in range(3)]
        n = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
        d = sum(n[k] * out[k] for k in range(3))
        assert d != 0, "degenerate or edge-on triangle"
        self.f.append((ia, ib, ic) if d > 0 else (ia, ic, ib))

    def quad(self, a, b, c, d, out):
        """Quad a-b-c-d (in order around it) as two triangles on its shorter diagonal."""
        ac = sum((a[k] - c[k]) ** 2 for k in range(3))
        bd = sum((b[k] - d[k]) ** 2 for k in range(3))
        if ac <= bd:
            self.tri(a, b, c, out)
            self.tri(a, c, d, out)
        else:
            self.tri(a, b, d, out)
            self.tri(b, c, d, out)

    def strip(self, side0, side1, out):
        """Quads between two polylines with the same number of points."""
        assert len(side0) == len(side1)
        for i in range(len(side0) - 1):
            self.quad(side0[i], side0[i + 1], side1[i + 1], side1[i], out)


def ring(us, vs):
    """The boundary of the rectangle us x vs, counter-clockwise in (u, v), every sample once."""
    pts = [(u, vs[0]) for u in us[:-1]]
    pts += [(us[-1], v) for v in vs[:-1]]
    pts += [(u, vs[-1]) for u in reversed(us[1:])]
    pts += [(us[0], v) for v in reversed(vs[1:])]
    return pts


def plate_with_hole(m, us, vs, center, w0, w1, embed, axis):
    """A plate us x vs x [w0, w1] in local (u, v, w) with a round hole along w; only its two
    faces w = w0, w = w1 and the hole's wall (the side walls are made by the caller).
    embed(u, v, w) gives the 3D point; axis is the unit 3D direction of +w."""
    outer = ring(us, vs)
    cu, cv = center
    inner = []
    for (u, v) in outer:
        a = math.atan2(v - cv, u - cu)
        inner.append((cu + HOLE_R * math.cos(a), cv + HOLE_R * math.sin(a)))
    n = len(outer)
    for w, sign in ((w0, -1.0), (w1, 1.0)):
        out = tuple(sign * c for c in axis)
        for i in range(n):
            j = (i + 1) % n
            m.quad(embed(*outer[i], w), embed(*outer[j], w), embed(*inner[j], w), embed(*inner[i], w), out)
    for i in range(n):
        j = (i + 1) % n
        mid_u = 0.5 * (inner[i][0] + inner[j][0])
        mid_v = 0.5 * (inner[i][1] + inner[j][1])
        # The body is outside the hole: outward points towards the axis of the hole.
        out = tuple(x - y for x, y in zip(embed(cu, cv, 0.0), embed(mid_u, mid_v, 0.0)))
        m.quad(embed(*inner[i], w0), embed(*inner[j], w0), embed(*inner[j], w1), embed(*inner[i], w1), out)


def bracket():
    m = Mesh()
    xs = lin(0.5, 4.0, NX)   # base plate, along x
    ys = lin(Y0, Y1, NY)     # both plates, along y
    zs = lin(0.5, 4.0, NX)   # upright, along z

    # Base plate: (u, v, w) = (x, y, z), hole along z.
    plate_with_hole(m, xs, ys, (2.25, 0.0), 0.0, 0.5, lambda u, v, w: (u, v, w), (0.0, 0.0, 1.0))
    # Upright: (u, v, w) = (y, z, x), hole along x.
    plate_with_hole(m, ys, zs, (0.0, 2.25), 0.0, 0.5, lambda u, v, w: (w, u, v), (1.0, 0.0, 0.0))

    # The corner block's outer faces x = 0 and z = 0, sampled along y like the plates.
    m.strip([(0.0, y, 0.0) for y in ys], [(0.0, y, 0.5) for y in ys], (-1.0, 0.0, 0.0))
    m.strip([(0.0, y, 0.0) for y in ys], [(0.5, y, 0.0) for y in ys], (0.0, 0.0, -1.0))
    # Ends: x = 4 of the base plate, z = 4 of the upright.
    m.strip([(4.0, y, 0.0) for y in ys], [(4.0, y, 0.5) for y in ys], (1.0, 0.0, 0.0))
    m.strip([(0.0, y, 4.0) for y in ys], [(0.5, y, 4.0) for y in ys], (0.0, 0.0, 1.0))
    # The two L-shaped sides y = Y0 and y = Y1.
    for y, s in ((Y0, -1.0), (Y1, 1.0)):
        out = (0.0, s, 0.0)
        m.strip([(x, y, 0.0) for x in xs], [(x, y, 0.5) for x in xs], out)  # base plate
        m.strip([(0.0, y, z) for z in zs], [(0.5, y, z) for z in zs], out)  # upright
        m.quad((0.0, y, 0.0), (0.5, y, 0.0), (0.5, y, 0.5), (0.0, y, 0.5), out)  # corner block
    return m


def check_closed(m):
    directed = {}
    for f in m.f:
        for k in range(3):
            e = (f[k], f[(k + 1) % 3])
            assert e not in directed, "edge %s used twice in the same direction" % (e,)
            directed[e] = True
    for (a, b) in directed:
        assert (b, a) in directed, "boundary edge %s" % ((a, b),)


def volume(m):
    vol = 0.0
    for a, b, c in m.f:
        pa, pb, pc = m.v[a], m.v[b], m.v[c]
        vol += (pa[0] * (pb[1] * pc[2] - pb[2] * pc[1]) - pa[1] * (pb[0] * pc[2] - pb[2] * pc[0]) +
                pa[2] * (pb[0] * pc[1] - pb[1] * pc[0]))
    return vol / 6.0


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    path = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "data", "meshes", "bracket.off")
    m = bracket()
    check_closed(m)
    vol = volume(m)
    assert vol > 0
    with open(path, "w") as out:
        out.write("OFF\n%d %d 0\n" % (len(m.v), len(m.f)))
        for p in m.v:
            out.write("%s %s %s\n" % tuple(repr(c) for c in p))
        for f in m.f:
            out.write("3 %d %d %d\n" % f)
    print("%s: %d vertices, %d triangles, volume %.6f" % (path, len(m.v), len(m.f), vol), file=sys.stderr)


if __name__ == "__main__":
    main()
