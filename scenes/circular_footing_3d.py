"""Revolves the meridian triangles of circular_footing_3d.geo a quarter turn about the y
axis into P2 tetrahedra: the quarter cylinder x ≥ 0, z ≥ 0 of the axisymmetric run's
mesh, for scenes/circular_footing_3d.toml (docs/3d.md, 'The circular footing against its
axisymmetric run').

    python3 circular_footing_3d.py [--layers 4] [-setnumber NAME VALUE ...] [-o FILE]

Each meridian triangle swept through one layer (π/2 / layers) is a prism, cut into three
tetrahedra by the rule that makes neighbours agree: with the triangle's vertices ordered
by a global index (a < b < c), every side quad is cut along the diagonal from the lower
vertex's near copy to the higher one's far copy, giving (a0 a1 b1 c1), (a0 b0 c0 c1),
(a0 b0 c1 b1). Axis vertices come first in the order and are one node for every layer,
so a prism with a vertex on the axis drops the first (flat) tetrahedron and one with an
edge on it keeps only the second. Mid-edge nodes are the midpoints in (r, θ, y), so
edges along the circumference lie on their circle (the footing's disc, the outer face)
and the meridian's straight edges keep their midpoints: the axisymmetric mesh's nodes
are the 3D mesh's on every layer plane. Written by Gmsh (MSH 4.1) as a discrete volume
`soil` and the physical surfaces footing (y = 0, r ≤ R), surface (y = 0, r ≥ R), base
(y = -H), outer (r = L), sym_x (x = 0), sym_z (z = 0).
"""
import math
import os
import sys

import gmsh

R, L, H = 0.5, 1.5, 1.5


def main():
    args = sys.argv[1:]
    here = os.path.dirname(os.path.abspath(__file__))
    layers, out, numbers = 4, os.path.join(here, "circular_footing_3d.msh"), []
    while args:
        a = args.pop(0)
        if a == "--layers":
            layers = int(args.pop(0))
        elif a == "-o":
            out = args.pop(0)
        elif a == "-setnumber":
            numbers.append((args.pop(0), float(args.pop(0))))
        else:
            sys.exit(f"unknown argument {a}")
    # Gmsh's own -setnumber, so the .geo's DefineConstant takes the value.
    argv = ["gmsh"] + [a for name, value in numbers for a in ("-setnumber", name, str(value))]
    gmsh.initialize(argv)
    gmsh.option.setNumber("General.Verbosity", 2)
    gmsh.open(os.path.join(here, "circular_footing_3d.geo"))
    gmsh.model.mesh.generate(2)
    tags, coords, _ = gmsh.model.mesh.getNodes()
    point = {int(t): (coords[3 * i], coords[3 * i + 1]) for i, t in enumerate(tags)}
    triangles = []
    for s in (1, 2):
        _, _, nodes = gmsh.model.mesh.getElements(2, s)
        n = [int(t) for t in nodes[0]]
        triangles += [n[3 * k : 3 * k + 3] for k in range(len(n) // 3)]
    gmsh.clear()

    eps = 1e-9 * L
    on_axis = {t: point[t][0] < eps for t in point}
    # Global order: axis vertices first.
    order = sorted(point, key=lambda t: (not on_axis[t], t))
    rank = {t: i for i, t in enumerate(order)}
    dtheta = 0.5 * math.pi / layers

    # Vertex ids: (meridian node, layer k) -> id; one id per axis node.
    vid, cyl = {}, []

    def vertex(t, k):
        key = (t, 0 if on_axis[t] else k)
        if key not in vid:
            vid[key] = len(cyl)
            r, y = point[t]
            cyl.append((r, 0.5 * math.pi if k == layers else k * dtheta, y))
        return vid[key]

    def xyz(c):
        # The last layer's plane is exactly x = 0 (cos(π/2) is 6e-17 in floating point).
        r, th, y = c
        x = 0.0 if th == 0.5 * math.pi else r * math.cos(th)
        return (x, y, r * math.sin(th))

    tets = []
    for tri in triangles:
        a, b, c = sorted(tri, key=rank.get)
        for k in range(layers):
            v = lambda t, j: vertex(t, k + j)
            cand = [
                (v(a, 0), v(a, 1), v(b, 1), v(c, 1)),
                (v(a, 0), v(b, 0), v(c, 0), v(c, 1)),
                (v(a, 0), v(b, 0), v(c, 1), v(b, 1)),
            ]
            for t in cand:
                if len(set(t)) < 4:
                    continue
                p = [xyz(cyl[i]) for i in t]
                d = [[p[j][m] - p[0][m] for m in range(3)] for j in (1, 2, 3)]
                det = (
                    d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1])
                    - d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0])
                    + d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0])
                )
                assert abs(det) > 1e-14, "flat tetrahedron"
                tets.append(t if det > 0 else (t[0], t[2], t[1], t[3]))

    # Mid-edge nodes, midpoints in (r, θ, y); θ of an axis vertex is the other's.
    mids = {}

    def mid(i, j):
        key = (min(i, j), max(i, j))
        if key not in mids:
            (r1, t1, y1), (r2, t2, y2) = cyl[i], cyl[j]
            if r1 < eps:
                t1 = t2
            if r2 < eps:
                t2 = t1
            mids[key] = len(cyl)
            cyl.append((0.5 * (r1 + r2), 0.5 * (t1 + t2), 0.5 * (y1 + y2)))
        return mids[key]

    # Gmsh's Tet10: vertices, then edges 01, 12, 20, 30, 32, 31.
    edges = [(0, 1), (1, 2), (2, 0), (3, 0), (3, 2), (3, 1)]
    tet10 = [list(t) + [mid(t[i], t[j]) for i, j in edges] for t in tets]

    # Boundary faces: the faces of one tetrahedron only, outward (the reader turns them).
    count = {}
    for t in tets:
        for f in ((t[0], t[1], t[2]), (t[0], t[1], t[3]), (t[0], t[2], t[3]), (t[1], t[2], t[3])):
            key = tuple(sorted(f))
            count[key] = count.get(key, 0) + 1
    groups = {g: [] for g in ("footing", "surface", "base", "outer", "sym_x", "sym_z")}
    for f, n in count.items():
        if n != 1:
            continue
        c = [cyl[i] for i in f]
        p = [xyz(x) for x in c]
        if all(abs(q[1]) < eps for q in p):
            g = "footing" if all(x[0] <= R + eps for x in c) else "surface"
        elif all(abs(q[1] + H) < eps for q in p):
            g = "base"
        elif all(abs(x[0] - L) < eps for x in c):
            g = "outer"
        elif all(abs(q[0]) < eps for q in p):
            g = "sym_x"
        elif all(abs(q[2]) < eps for q in p):
            g = "sym_z"
        else:
            raise SystemExit(f"unclassified boundary face {p}")
        groups[g].append(list(f) + [mid(f[0], f[1]), mid(f[1], f[2]), mid(f[2], f[0])])

    gmsh.model.add("circular_footing_3d")
    vol = gmsh.model.addDiscreteEntity(3)
    coords = [c for x in cyl for c in xyz(x)]
    gmsh.model.mesh.addNodes(3, vol, list(range(1, len(cyl) + 1)), coords)
    gmsh.model.mesh.addElementsByType(vol, 11, [], [i + 1 for t in tet10 for i in t])
    gmsh.model.addPhysicalGroup(3, [vol], name="soil")
    for name, faces in groups.items():
        s = gmsh.model.addDiscreteEntity(2)
        gmsh.model.mesh.addElementsByType(s, 9, [], [i + 1 for f in faces for i in f])
        gmsh.model.addPhysicalGroup(2, [s], name=name)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.SaveAll", 0)
    gmsh.write(out)
    gmsh.finalize()
    print(f"{out}: {len(triangles)} meridian triangles x {layers} layers -> "
          f"{len(tets)} P2 tetrahedra, {len(cyl)} nodes ({3 * len(cyl)} unknowns before "
          f"boundary conditions); faces " + ", ".join(f"{g} {len(v)}" for g, v in groups.items()))


main()
