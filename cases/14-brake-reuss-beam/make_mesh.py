#!/usr/bin/env python3
"""Writes brb.inp: the Brake-Reuss beam (two steel half-beams bolted in a lap joint) as an
Abaqus assembly deck of C3D8I hexahedra, with the three bolt holes cut out of the lap.

Geometry (millimetres here, metres in the deck; README.md): each half-beam is 420 mm long with
a 25.4 x 25.4 mm section and is cut to half thickness (12.7 mm) over the 120 mm lap; holes of
8.5 mm diameter at x = -30, 0, +30 mm. Coordinates: x along the beam with the lap centred at
x = 0, y across its width (|y| <= 12.7), z through the thickness with the interface at z = 0.

One part, HALF_BEAM, is meshed: the lower half (x in [-360, 60]; lap z in [-12.7, 0]). The deck
places it twice: instance LOWER as it is, instance UPPER turned by 180 degrees about the y axis
((x, y, z) -> (-x, y, -z)). The lap's in-plane node layout is symmetric about x = 0, so the two
lap faces have coincident nodes (separate nodes per instance), as the zero-thickness interface
needs.

Lap, in plane: around each hole an O-grid (square-to-circle mapped block) over the full width,
25.4 x 25.4 mm: 40 nodes on the hole circle (r = 4.25 mm) and on a ring at the washer's outer
radius (8.73 mm), three polar layers between them and three blended layers out to the square,
whose sides carry the 2.54 mm seed; structured blocks between the squares and at the lap's ends.
Three elements through each 12.7 mm half-thickness (six through the 25.4 mm arm). Along the arm
the elements grow geometrically from 2.54 mm at the lap to 7.5 mm.

Names (prefixed LOWER. / UPPER. in the assembly): element sets BEAM (all), LAP, LAP_INNER (the
lap's layer on the interface), LAP_OUTER (its layer on the outer face); surfaces LAP_FACE (the
interface side of the lap, holes excluded since they are not meshed) and WASHER_FACE (the lap's
outer face, where washers and bolt heads or nuts press); node set FREE_END (x = -360 mm).

    /usr/bin/python3 make_mesh.py            # rewrites brb.inp next to this script
    /usr/bin/python3 make_mesh.py --out coarse.inp --hole-segments 24 --seed 4.2333 --arm-max 12

The output is a function of the arguments only (same bytes on every run).
"""
import argparse
import math
from pathlib import Path

# Geometry [mm]
HALF_LENGTH = 420.0
LAP = 120.0
WIDTH = 25.4
THICK = 25.4
HOLE_RADIUS = 4.25
WASHER_RADIUS = 8.73           # 0.34375 in: outer radius of a 5/16-in washer
HOLES = (-30.0, 0.0, 30.0)
E, NU, RHO = 200.0e9, 0.29, 7800.0


def arm_lengths(first, largest, total, growth):
    """Element lengths along the arm: geometric from `first`, capped at `largest`, scaled to
    fill `total` exactly."""
    lengths = []
    h = first
    while sum(lengths) < total - 1e-9:
        lengths.append(min(h, largest))
        h *= growth
    return [h * total / sum(lengths) for h in lengths]


class Mesh:
    """Nodes merged by position (within the one part), hexahedra in Abaqus C3D8 order."""

    def __init__(self):
        self.nodes = []      # (x, y, z) [mm]
        self.index = {}
        self.elements = []   # 8 node indices: 1-4 counter-clockwise seen from +z, 5-8 above
        self.sets = {}

    def node(self, x, y, z):
        key = (round(x * 1e6), round(y * 1e6), round(z * 1e6))  # nanometre grid
        if key not in self.index:
            self.index[key] = len(self.nodes)
            self.nodes.append((x, y, z))
        return self.index[key]

    def hexa(self, quad, z0, z1):
        """The hexahedron over a counter-clockwise quad of (x, y) points between z0 < z1."""
        bottom = [self.node(x, y, z0) for (x, y) in quad]
        top = [self.node(x, y, z1) for (x, y) in quad]
        self.elements.append(bottom + top)
        return len(self.elements) - 1


def signed_area(quad):
    return 0.5 * sum(quad[i][0] * quad[(i + 1) % 4][1] - quad[(i + 1) % 4][0] * quad[i][1] for i in range(4))


def square_point(k, n, half):
    """Point k of n (n divisible by 4) on the square [-half, half]^2, starting at the corner
    (half, -half) and going counter-clockwise, uniformly spaced along each side."""
    side, j = divmod(k % n, n // 4)
    s = -half + 2.0 * half * j / (n // 4)
    if side == 0:
        return (half, s)
    if side == 1:
        return (-s, half)
    if side == 2:
        return (-half, -s)
    return (s, -half)


def ogrid_quads(xc, half, segments, polar_layers, blend_layers):
    """Quads of the square-to-circle block around the hole at (xc, 0): rings 0..polar_layers are
    circles from the hole to the washer radius (node k at angle -45 deg + k 360/segments deg,
    corners of the square at the diagonals), then straight blends to the square's points."""
    def point(k, ring):
        k %= segments
        if ring <= polar_layers:
            r = HOLE_RADIUS + (WASHER_RADIUS - HOLE_RADIUS) * ring / polar_layers
            angle = math.radians(-45.0 + 360.0 * k / segments)
            return (xc + r * math.cos(angle), r * math.sin(angle))
        t = (ring - polar_layers) / blend_layers
        angle = math.radians(-45.0 + 360.0 * k / segments)
        inner = (WASHER_RADIUS * math.cos(angle), WASHER_RADIUS * math.sin(angle))
        outer = square_point(k, segments, half)
        return (xc + (1 - t) * inner[0] + t * outer[0], (1 - t) * inner[1] + t * outer[1])

    quads = []
    for ring in range(polar_layers + blend_layers):
        for k in range(segments):
            quads.append([point(k, ring), point(k, ring + 1), point(k + 1, ring + 1), point(k + 1, ring)])
    return quads


def grid_quads(x0, x1, nx, half, ny):
    quads = []
    for i in range(nx):
        xa, xb = x0 + (x1 - x0) * i / nx, x0 + (x1 - x0) * (i + 1) / nx
        for j in range(ny):
            ya, yb = -half + 2 * half * j / ny, -half + 2 * half * (j + 1) / ny
            quads.append([(xa, ya), (xb, ya), (xb, yb), (xa, yb)])
    return quads


def lap_quads(seed, segments, polar_layers, blend_layers):
    """The lap's in-plane quads, counter-clockwise, symmetric about x = 0."""
    half = WIDTH / 2
    ny = segments // 4
    quads, x = [], -LAP / 2
    for xc in HOLES:
        gap = (xc - half) - x
        if gap > 1e-9:
            quads += grid_quads(x, xc - half, max(1, round(gap / seed)), half, ny)
        quads += ogrid_quads(xc, half, segments, polar_layers, blend_layers)
        x = xc + half
    quads += grid_quads(x, LAP / 2, max(1, round((LAP / 2 - x) / seed)), half, ny)
    for q in quads:
        if signed_area(q) < 0:
            q.reverse()
    return quads


def build(args):
    segments = args.hole_segments
    if segments % 4:
        raise SystemExit("--hole-segments must be divisible by 4")
    half_w, half_t = WIDTH / 2, THICK / 2
    ny = segments // 4                        # the square's side carries the width's seed
    layers = args.layers                      # through each 12.7 mm half-thickness
    z = [-half_t + THICK * k / (2 * layers) for k in range(2 * layers + 1)]  # the arm's levels
    mesh = Mesh()
    lap, inner, outer = [], [], []
    for quad in lap_quads(args.seed, segments, args.polar_layers, args.blend_layers):
        for k in range(layers):               # the lap: z in [-12.7, 0]
            e = mesh.hexa(quad, z[k], z[k + 1])
            lap.append(e)
            if k == layers - 1:
                inner.append(e)
            if k == 0:
                outer.append(e)
    # The arm: x from -60 down to -360 mm, full thickness; its first station shares the lap's end.
    stations = [-LAP / 2]
    for h in arm_lengths(args.seed, args.arm_max, HALF_LENGTH - LAP, args.arm_growth):
        stations.append(stations[-1] - h)
    stations[-1] = LAP / 2 - HALF_LENGTH
    for i in range(len(stations) - 1):
        xa, xb = stations[i + 1], stations[i]
        for j in range(ny):
            ya, yb = -half_w + WIDTH * j / ny, -half_w + WIDTH * (j + 1) / ny
            for k in range(2 * layers):
                mesh.hexa([(xa, ya), (xb, ya), (xb, yb), (xa, yb)], z[k], z[k + 1])
    mesh.sets = {"LAP": lap, "LAP_INNER": inner, "LAP_OUTER": outer}
    free_end = [i for i, (x, _, _) in enumerate(mesh.nodes) if abs(x - stations[-1]) < 1e-9]
    return mesh, free_end


def number(value_mm):
    v = value_mm * 1e-3 + 0.0  # metres; + 0.0 turns -0.0 into 0.0
    return f"{v:.12g}"


def rows(ids, per_line=16):
    ids = [str(i) for i in ids]
    return [", ".join(ids[s:s + per_line]) for s in range(0, len(ids), per_line)]


def deck(mesh, free_end, args):
    n_nodes, n_elements = len(mesh.nodes), len(mesh.elements)
    lines = [
        "** Brake-Reuss beam for jointhb cases/14-brake-reuss-beam, written by make_mesh.py",
        f"** options: seed {args.seed} mm, hole segments {args.hole_segments}, polar layers "
        f"{args.polar_layers}, blend layers {args.blend_layers}, layers {args.layers}, arm max "
        f"{args.arm_max} mm, arm growth {args.arm_growth}",
        f"** per half-beam: {n_nodes} nodes, {n_elements} C3D8I elements; units m, kg, s, N, Pa",
        "*PART, NAME=HALF_BEAM",
        "*NODE",
    ]
    lines += [f"{i + 1}, {number(x)}, {number(y)}, {number(z)}" for i, (x, y, z) in enumerate(mesh.nodes)]
    lines.append("*ELEMENT, TYPE=C3D8I")
    lines += [f"{e + 1}, " + ", ".join(str(n + 1) for n in nodes) for e, nodes in enumerate(mesh.elements)]
    lines += ["*ELSET, ELSET=BEAM, GENERATE", f"1, {n_elements}, 1"]
    for name in ("LAP", "LAP_INNER", "LAP_OUTER"):
        lines.append(f"*ELSET, ELSET={name}")
        lines += rows(e + 1 for e in mesh.sets[name])
    # S2 is the face of nodes 5-8 (z-max), S1 that of nodes 1-4 (z-min).
    lines += ["*SURFACE, NAME=LAP_FACE, TYPE=ELEMENT", "LAP_INNER, S2",
              "*SURFACE, NAME=WASHER_FACE, TYPE=ELEMENT", "LAP_OUTER, S1",
              "*NSET, NSET=FREE_END"]
    lines += rows(i + 1 for i in free_end)
    lines += ["*SOLID SECTION, ELSET=BEAM, MATERIAL=STEEL", ",", "*END PART",
              "*ASSEMBLY, NAME=BRB",
              "*INSTANCE, NAME=LOWER, PART=HALF_BEAM", "*END INSTANCE",
              "** turned by 180 degrees about the y axis: (x, y, z) -> (-x, y, -z)",
              "*INSTANCE, NAME=UPPER, PART=HALF_BEAM", "0., 0., 0.", "0., 0., 0., 0., 1., 0., 180.",
              "*END INSTANCE", "*END ASSEMBLY",
              "*MATERIAL, NAME=STEEL", "*ELASTIC", f"{E:.6g}, {NU}", "*DENSITY", f"{RHO:.6g}"]
    return "\n".join(lines) + "\n"


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--out", default=str(Path(__file__).with_name("brb.inp")), help="output file")
    p.add_argument("--seed", type=float, default=2.54, help="in-plane seed of the lap and first arm element [mm]")
    p.add_argument("--hole-segments", type=int, default=40, help="nodes on each hole circle (divisible by 4)")
    p.add_argument("--polar-layers", type=int, default=3, help="element rings from the hole to the washer radius")
    p.add_argument("--blend-layers", type=int, default=3, help="element rings from the washer radius to the square")
    p.add_argument("--layers", type=int, default=3, help="elements through each 12.7 mm half-thickness")
    p.add_argument("--arm-max", type=float, default=7.5, help="largest element length along the arm [mm]")
    p.add_argument("--arm-growth", type=float, default=1.08, help="growth ratio of the arm's elements")
    args = p.parse_args()
    mesh, free_end = build(args)
    Path(args.out).write_text(deck(mesh, free_end, args))
    print(f"{args.out}: per half-beam {len(mesh.nodes)} nodes, {len(mesh.elements)} elements")


if __name__ == "__main__":
    main()
