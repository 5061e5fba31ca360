#!/usr/bin/env python3
"""Writes bracket.inp: a steel angle bracket (an L section, not a box) meshed with C3D8I
hexahedra, in the Abaqus/CalculiX format a commercial pre-processor exports. jointhb reads the
mesh cards (*NODE, *ELEMENT, *NSET, *ELSET, *SURFACE) and skips the material and section cards
with a warning: materials come from the case file.

Geometry (metres; README.md): the foot is 60 x 30 x 5 mm and lies on the plate's top face
(z = 4 mm); the upright flange is 5 mm thick and rises 55 mm above the foot at x = 0 ... 5 mm.
In-plane spacing 2.5 mm, matching the plate's box mesh in case.yaml so that the foot's underside
and the plate's top face have coincident nodes (the zero-thickness interface needs matching
meshes).

    /usr/bin/python3 make_mesh.py            # rewrites bracket.inp next to this script
"""
from pathlib import Path

H = 0.0025                      # element edge [m]
NX, NY = 24, 12                 # foot: 60 mm along x, 30 mm along y
FOOT_Z = [0.004, 0.0065, 0.009]  # plate top, mid-foot, foot top: 2 elements through 5 mm
FLANGE_COLUMNS = 2              # the flange is the first 2 columns (x = 0 ... 5 mm)
FLANGE_LAYERS = 22              # 55 mm above the foot


def z_levels():
    return FOOT_Z + [FOOT_Z[-1] + H * (k + 1) for k in range(FLANGE_LAYERS)]


def has_node(i, k):
    """Node column i (along x) exists at level k: everywhere in the foot, only x <= 5 mm above."""
    return k < len(FOOT_Z) or i <= FLANGE_COLUMNS


def has_element(i, k):
    return k < len(FOOT_Z) - 1 or i < FLANGE_COLUMNS


def main():
    z = z_levels()
    ids = {}
    lines = ["** Steel angle bracket for jointhb cases/07-angle-bracket (written by make_mesh.py)",
             "*HEADING", "angle bracket, C3D8I, 2.5 mm", "*NODE"]
    for k in range(len(z)):
        for j in range(NY + 1):
            for i in range(NX + 1):
                if has_node(i, k):
                    ids[i, j, k] = len(ids) + 1
                    lines.append(f"{ids[i, j, k]}, {i * H:.6g}, {j * H:.6g}, {z[k]:.6g}")
    lines.append("*ELEMENT, TYPE=C3D8I, ELSET=BRACKET")
    elements = {}
    for k in range(len(z) - 1):
        for j in range(NY):
            for i in range(NX):
                if not has_element(i, k):
                    continue
                elements[i, j, k] = len(elements) + 1
                # Abaqus C3D8: nodes 1-4 counter-clockwise on the z-min face, 5-8 above them.
                corners = [(i, j, k), (i + 1, j, k), (i + 1, j + 1, k), (i, j + 1, k)]
                n = [ids[c] for c in corners] + [ids[a, b, c + 1] for (a, b, c) in corners]
                lines.append(f"{elements[i, j, k]}, " + ", ".join(map(str, n)))

    def element_set(name, keys):
        lines.append(f"*ELSET, ELSET={name}")
        numbers = [str(elements[key]) for key in sorted(keys, key=lambda t: (t[2], t[1], t[0]))]
        for start in range(0, len(numbers), 16):
            lines.append(", ".join(numbers[start:start + 16]))

    # The foot's underside (face S1 = nodes 1-2-3-4, z-min) faces the plate; its top (S2) away
    # from the flange carries the bolt heads.
    element_set("FOOT_LOWER", [(i, j, 0) for i in range(NX) for j in range(NY)])
    element_set("FOOT_UPPER", [(i, j, 1) for i in range(FLANGE_COLUMNS, NX) for j in range(NY)])
    lines += ["*SURFACE, NAME=FOOT_UNDERSIDE, TYPE=ELEMENT", "FOOT_LOWER, S1",
              "*SURFACE, NAME=FOOT_TOP, TYPE=ELEMENT", "FOOT_UPPER, S2"]
    lines.append("*NSET, NSET=FLANGE_TIP")
    tip = [str(ids[i, j, len(z) - 1]) for j in range(NY + 1) for i in range(FLANGE_COLUMNS + 1)]
    for start in range(0, len(tip), 16):
        lines.append(", ".join(tip[start:start + 16]))
    # What an exporter also writes; jointhb skips these cards and says so.
    lines += ["*MATERIAL, NAME=STEEL", "*ELASTIC", "210000e6, 0.3", "*DENSITY", "7850.",
              "*SOLID SECTION, ELSET=BRACKET, MATERIAL=STEEL", ","]
    out = Path(__file__).with_name("bracket.inp")
    out.write_text("\n".join(lines) + "\n")
    print(f"{out}: {len(ids)} nodes, {len(elements)} elements")


if __name__ == "__main__":
    main()
