#!/usr/bin/python3
"""Writes the bad-input corpus (tests/corpus/bad/): case files, meshes, CSVs and command lines that
jointhb must refuse, each with what it must say.

Every entry is one valid base input with one defect put in on purpose, so the expected reaction is
known independently of jointhb's output: exit code 2 (bad input), exactly one line on stderr, the
command's prefix ("jointhb run: ", "jointhb fit: ", "jointhb loop: "), and the text that names the
defect (the file and key path the mutation touched, or the mesh/CSV file and line).

Each case file starts with a comment line
    # expect: exit=2 command=run text=<text the error line must contain>
(for CSV and mesh defects the case file carrying the comment refers to the defective file next to
it). Command lines are in cli_lines.txt: "<exit>\t<text>\t<arguments>".

Regenerate (deterministic; review the diff):  /usr/bin/python3 tests/corpus/generate_corpus.py
The corpus is run by run_corpus.py (ctest: corpus.bad_inputs).
"""
import copy
import os
import shutil
import sys

import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "bad")

# ---- base inputs (valid; each is read by jointhb without error) --------------------------------
DISCRETE_FRF = {
    "model": {"type": "discrete", "mass": [[1.0, 0.0], [0.0, 1.0]],
              "stiffness": [[2.0e4, -1.0e4], [-1.0e4, 2.0e4]],
              "damping": {"rayleigh": {"alpha": 0.0, "beta": 1.0e-4}}},
    "contacts": [{"law": "jenkins", "dofs": [1], "kt0": 5.0e3, "mu": 0.3, "normal_force": 10.0},
                 {"law": "gaul-mayer", "dofs": [0, 1], "kt0": 1.0e4, "mu": 0.3, "normal_force": 20.0,
                  "n": 0.3333333333333333}],
    "excitation": [{"dof": 0, "amplitude": [0.05, 0.5]}],
    "analysis": {"frf": {"omega": [70.0, 150.0], "harmonics": 7, "time_samples": 128, "output_dof": 1}},
}
DISCRETE_MODES = {
    "model": {"type": "discrete", "mass": [[1.0]], "stiffness": [[1.0e4]],
              "damping": {"modal": [0.002]}},
    "contacts": [{"law": "gaul-mayer", "dofs": [0], "kt0": 3.0e4, "mu": 0.2, "normal_force": 5.0,
                  "n": 0.3333333333333333}],
    "analysis": {"nonlinear_modes": {"mode": 1, "log10_amplitude": [-8, -3.5], "harmonics": 7,
                                     "time_samples": 128}},
}
LOOP_SWEEP = {
    "analysis": {"loop_sweep": {"law": "gaul-mayer", "n": 0.3333333333333333, "mu": 0.3,
                                "normal_force": 100.0, "kt0": 1.0e6,
                                "amplitude_over_gmax": [1.0e-6, 10.0], "points": 41,
                                "time_samples": 256}},
}
FE_BOX = {
    "model": {
        "type": "fe",
        "materials": {"aluminium": {"youngs_modulus": 70.0e9, "poissons_ratio": 0.33, "density": 2700.0}},
        "parts": [
            {"name": "lower", "material": "aluminium", "element": "C3D8I",
             "box": {"origin": [0.0, 0.0, 0.0], "size": [0.100, 0.030, 0.004], "divisions": [10, 3, 1]}},
            {"name": "upper", "material": "aluminium", "element": "C3D8I",
             "box": {"origin": [0.060, 0.0, 0.004], "size": [0.100, 0.030, 0.004], "divisions": [10, 3, 1]}},
        ],
        "interfaces": [{
            "name": "lap", "bottom": "lower.zmax", "top": "upper.zmin",
            "region": {"min": [0.060, 0.0, 0.0039], "max": [0.100, 0.030, 0.0041]},
            "integration": "nodal",
            "contact": {"pressure": 1.0e6, "decay": 1.0e6, "mu": 0.3, "law": "gaul-mayer",
                        "n": 0.3333333333333333, "stiffness_ratio": 0.8},
        }],
        "bolts": [{"name": "bolt-1", "point": [0.080, 0.015, 0.0], "direction": [0.0, 0.0, 1.0],
                   "head": {"surface": "upper.zmax", "radius": 0.008},
                   "nut": {"surface": "lower.zmin", "radius": 0.008},
                   "stiffness": 5.0e8, "preload": 5000.0}],
    },
    "analysis": {"preload": {"load_steps": 4, "tolerance": 1.0e-9},
                 "modes": {"count": 8, "shift_hz": -10.0}},
}
FIT = {
    "model": {"type": "discrete", "mass": 1.0, "stiffness": 1.0e4, "damping": {"modal": [0.01]}},
    "contacts": [{"law": "gaul-mayer", "dofs": [0], "kt0": 5.0e3, "mu": 0.2, "normal_force": 40.0,
                  "n": 0.3333333333333333}],
    "analysis": {"nonlinear_modes": {"mode": 1, "log10_amplitude": [-7, -3.5], "harmonics": 3}},
    "fit": {
        "parameters": [
            {"name": "contacts[0].normal_force", "lower": 0.5, "upper": 50.0, "start": 40.0, "log_scale": True},
            {"name": "contacts[0].kt0", "lower": 3.0e3, "upper": 3.0e5, "start": 5.0e3, "log_scale": True}],
        "targets": [{"type": "backbone", "mode": 1, "file": "measured.csv"}],
        "algorithm": "bobyqa", "xtol": 1.0e-5, "max_evaluations": 300,
    },
}
MEASURED = """amplitude,frequency_hz,damping_ratio,sigma_frequency_hz,sigma_damping_ratio
8.783711456e-07,31.81348302,0.001701355161,0.06363,3.403e-05
1.309241764e-06,31.75184265,0.002064392384,0.0635,4.129e-05
1.94244959e-06,31.84307324,0.00258687013,0.06369,5.174e-05
2.8918e-06,31.70,0.0032,0.0634,6.4e-05
"""
# Two C3D8 hexahedra as an Abaqus deck and as a Gmsh 4.1 file (the part is called "block").
NODES = [(i + 1, x, y, z) for i, (x, y, z) in enumerate(
    [(x, y, z) for z in (0.0, 0.01) for y in (0.0, 0.01) for x in (0.0, 0.01, 0.02)])]
HEXES = [(1, [1, 2, 5, 4, 7, 8, 11, 10]), (2, [2, 3, 6, 5, 8, 9, 12, 11])]
INP = "*NODE\n" + "".join(f"{n}, {x}, {y}, {z}\n" for n, x, y, z in NODES) + \
    "*ELEMENT, TYPE=C3D8, ELSET=block\n" + \
    "".join(f"{e}, " + ", ".join(map(str, c)) + "\n" for e, c in HEXES)
MSH = ("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
       "$PhysicalNames\n1\n3 1 \"block\"\n$EndPhysicalNames\n"
       "$Entities\n0 0 0 1\n1 0 0 0 0.02 0.01 0.01 1 1 0\n$EndEntities\n"
       f"$Nodes\n1 {len(NODES)} 1 {len(NODES)}\n3 1 0 {len(NODES)}\n"
       + "".join(f"{n}\n" for n, *_ in NODES) + "".join(f"{x} {y} {z}\n" for _, x, y, z in NODES)
       + "$EndNodes\n"
       f"$Elements\n1 {len(HEXES)} 1 {len(HEXES)}\n3 1 5 {len(HEXES)}\n"
       + "".join(f"{e} " + " ".join(map(str, c)) + "\n" for e, c in HEXES) + "$EndElements\n")
FE_MESH = {
    "model": {"type": "fe",
              "materials": {"steel": {"youngs_modulus": 2.1e11, "poissons_ratio": 0.3, "density": 7850.0}},
              "parts": [{"mesh": "MESH", "material": "steel"}]},
    "analysis": {"modes": {"count": 4, "shift_hz": -10.0}},
}


# ---- mutations of a YAML tree ------------------------------------------------------------------
def leaves(node, path=""):
    """(path, parent, key) of every scalar leaf, with jointhb's key-path spelling."""
    if isinstance(node, dict):
        for k, v in node.items():
            p = f"{path}.{k}" if path else k
            if isinstance(v, (dict, list)):
                yield from leaves(v, p)
            else:
                yield p, node, k
    elif isinstance(node, list):
        for i, v in enumerate(node):
            p = f"{path}[{i}]"
            if isinstance(v, (dict, list)):
                yield from leaves(v, p)
            else:
                yield p, node, i


def mappings(node, path=""):
    if isinstance(node, dict):
        yield path, node
        for k, v in node.items():
            yield from mappings(v, f"{path}.{k}" if path else k)
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from mappings(v, f"{path}[{i}]")


def key_text(path):
    # No closing quote: an error at an entry under the key (e.g. 'model.mass[0]') names it too.
    return f"key '{path}"


def numeric_mutations(base):
    """Numeric leaves: text, NaN, a list and a mapping where a number belongs."""
    for path, _, _ in list(leaves(base)):
        value = get(base, path)
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            continue
        for tag, new in (("text", "abc"), ("nan", float("nan")), ("list", [1, 2]), ("map", {"a": 1})):
            yield f"{tag}", path, set_at(base, path, new), key_text(path)


def string_mutations(base):
    for path, _, _ in list(leaves(base)):
        value = get(base, path)
        if not isinstance(value, str) or path.endswith(".name") or path.endswith("file") \
                or path.endswith("mesh") or path.endswith("material") or path.endswith("bottom") \
                or path.endswith("top") or path.endswith("surface"):
            continue
        yield "enum", path, set_at(base, path, "no-such-value"), key_text(path)
        yield "number", path, set_at(base, path, 17), key_text(path)


def unknown_key_mutations(base):
    for path, _ in list(mappings(base)):
        probe = copy.deepcopy(base)
        target = get(probe, path) if path else probe
        target["bogus_key"] = 1
        yield "unknown", path or "root", probe, key_text(f"{path}.bogus_key" if path else "bogus_key")


def get(tree, path):
    node = tree
    for part in split(path):
        node = node[part]
    return node


def set_at(tree, path, value):
    probe = copy.deepcopy(tree)
    parts = split(path)
    node = probe
    for part in parts[:-1]:
        node = node[part]
    node[parts[-1]] = value
    return probe


def split(path):
    parts = []
    for dotted in path.split("."):
        name, _, rest = dotted.partition("[")
        if name:
            parts.append(name)
        while rest:
            index, _, rest = rest.partition("]")
            parts.append(int(index))
            rest = rest[1:] if rest.startswith("[") else rest
    return parts


def dump(tree):
    return yaml.safe_dump(tree, sort_keys=False, default_flow_style=None, width=100)


# ---- writing -------------------------------------------------------------------------------------
ENTRIES = []


def write_case(name, tree_or_text, text, command="run", extra_files=()):
    body = tree_or_text if isinstance(tree_or_text, str) else dump(tree_or_text)
    path = os.path.join(OUT, name + ".yaml")
    with open(path, "w", encoding="utf-8", newline="") as f:
        f.write(f"# expect: exit=2 command={command} text={text}\n{body}")
    for file_name, content in extra_files:
        mode = "wb" if isinstance(content, bytes) else "w"
        with open(os.path.join(OUT, file_name), mode) as f:
            f.write(content)
    ENTRIES.append(name)


def yaml_cases():
    bases = [("frf", DISCRETE_FRF), ("modes", DISCRETE_MODES), ("sweep", LOOP_SWEEP), ("fe", FE_BOX)]
    for base_name, base in bases:
        n = 0
        for generator in (numeric_mutations, string_mutations, unknown_key_mutations):
            for tag, path, tree, text in generator(base):
                n += 1
                safe = path.replace(".", "_").replace("[", "_").replace("]", "")
                write_case(f"{base_name}-{n:03d}-{tag}-{safe}", tree, text)


def syntax_cases():
    good = dump(DISCRETE_FRF)
    cases = {
        "empty": ("", "empty"),
        "only-comment": ("# nothing here\n", "empty"),
        "tab-indent": (good.replace("  ", "\t", 1), "invalid YAML"),
        "unclosed-bracket": (good.replace("omega: [70.0, 150.0]", "omega: [70.0, 150.0", 1), "invalid YAML"),
        "two-documents": (good + "---\nmodel: {}\n", "second YAML document"),
        "duplicate-key": (good + "model: {type: discrete}\n", "key 'model'"),
        "scalar-root": ("42\n", "mapping"),
        "list-root": ("- a\n- b\n", "mapping"),
        "unknown-top": (good + "analyses: {}\n", "key 'analyses'"),
        "no-analysis": (dump({k: v for k, v in DISCRETE_FRF.items() if k != "analysis"}), "analysis"),
        "model-type": (dump(set_at(DISCRETE_FRF, "model.type", "beam")), "key 'model.type'"),
        "mass-not-square": (dump(set_at(DISCRETE_FRF, "model.mass", [[1.0, 0.0]])), "key 'model.mass"),
        "mass-negative": (dump(set_at(DISCRETE_FRF, "model.mass", [[-1.0, 0.0], [0.0, 1.0]])), "key 'model.mass"),
        "stiffness-asymmetric": (dump(set_at(DISCRETE_FRF, "model.stiffness", [[2.0e4, -1.0e4], [0.0, 2.0e4]])),
                                 "key 'model.stiffness"),
        "dof-out-of-range": (dump(set_at(DISCRETE_FRF, "contacts[0].dofs", [5])), "key 'contacts[0].dofs"),
        "dofs-three": (dump(set_at(DISCRETE_FRF, "contacts[0].dofs", [0, 1, 0])), "key 'contacts[0].dofs'"),
        "omega-one": (dump(set_at(DISCRETE_FRF, "analysis.frf.omega", [70.0])), "key 'analysis.frf.omega'"),
        "harmonics-zero": (dump(set_at(DISCRETE_FRF, "analysis.frf.harmonics", 0)), "key 'analysis.frf.harmonics'"),
        "harmonics-huge": (dump(set_at(DISCRETE_FRF, "analysis.frf.harmonics", 100000)), "key 'analysis.frf.harmonics'"),
        "samples-few": (dump(set_at(DISCRETE_FRF, "analysis.frf.time_samples", 4)), "key 'analysis.frf.time_samples'"),
        "mu-negative": (dump(set_at(DISCRETE_FRF, "contacts[0].mu", -0.3)), "key 'contacts[0].mu'"),
        "mu-zero": (dump(set_at(DISCRETE_FRF, "contacts[0].mu", 0.0)), "key 'contacts[0].mu'"),
        "n-one": (dump(set_at(DISCRETE_FRF, "contacts[1].n", 1.0)), "key 'contacts[1].n'"),
        "n-zero": (dump(set_at(DISCRETE_FRF, "contacts[1].n", 0.0)), "key 'contacts[1].n'"),
        "kt0-negative": (dump(set_at(DISCRETE_FRF, "contacts[0].kt0", -1.0)), "key 'contacts[0].kt0'"),
        "force-negative": (dump(set_at(DISCRETE_FRF, "contacts[0].normal_force", -10.0)),
                           "key 'contacts[0].normal_force'"),
        "mass-1e300": (dump(set_at(DISCRETE_FRF, "model.mass", [[1e300, 0.0], [0.0, 1.0]])), "key 'model.mass[0][0]'"),
        "force-1e200": (dump(set_at(DISCRETE_FRF, "excitation[0].amplitude", [1e200])), "key 'excitation[0].amplitude[0]'"),
        "kt0-tiny": (dump(set_at(DISCRETE_FRF, "contacts[0].kt0", 1e-150)), "key 'contacts[0].kt0'"),
        "omega-huge": (dump(set_at(DISCRETE_FRF, "analysis.frf.omega", [70.0, 1e150])), "key 'analysis.frf.omega[1]'"),
        "inf-mass": (dump(set_at(DISCRETE_FRF, "model.mass", [[float("inf"), 0.0], [0.0, 1.0]])), "key 'model.mass"),
        "output-dof": (dump(set_at(DISCRETE_FRF, "analysis.frf.output_dof", 2)), "key 'analysis.frf.output_dof'"),
        "stability-method": (dump(set_at(DISCRETE_FRF, "analysis.frf.stability_method", "shooting")),
                             "key 'analysis.frf.stability_method'"),
        "mode-zero": (dump(set_at(DISCRETE_MODES, "analysis.nonlinear_modes.mode", 0)),
                      "key 'analysis.nonlinear_modes.mode'"),
        "mode-beyond": (dump(set_at(DISCRETE_MODES, "analysis.nonlinear_modes.mode", 2)),
                        "key 'analysis.nonlinear_modes.mode'"),
        "amplitude-equal": (dump(set_at(DISCRETE_MODES, "analysis.nonlinear_modes.log10_amplitude", [-5, -5])),
                            "key 'analysis.nonlinear_modes.log10_amplitude"),
        "points-zero": (dump(set_at(LOOP_SWEEP, "analysis.loop_sweep.points", 0)), "key 'analysis.loop_sweep.points'"),
        "sweep-law": (dump(set_at(LOOP_SWEEP, "analysis.loop_sweep.law", "coulomb")), "key 'analysis.loop_sweep.law'"),
        "divisions-zero": (dump(set_at(FE_BOX, "model.parts[0].box.divisions", [0, 3, 1])),
                           "key 'model.parts[0].box.divisions[0]'"),
        "divisions-memory": (dump(set_at(FE_BOX, "model.parts[0].box.divisions", [100000, 100000, 100000])),
                             "key 'model.parts[0].box.divisions'"),
        "size-negative": (dump(set_at(FE_BOX, "model.parts[0].box.size", [-0.1, 0.03, 0.004])),
                          "key 'model.parts[0].box.size[0]'"),
        "unknown-material": (dump(set_at(FE_BOX, "model.parts[0].material", "steel")), "key 'model.parts[0].material'"),
        "unknown-surface": (dump(set_at(FE_BOX, "model.interfaces[0].bottom", "lower.wmax")),
                            "key 'model.interfaces[0].bottom'"),
        "poisson-half": (dump(set_at(FE_BOX, "model.materials.aluminium.poissons_ratio", 0.5)),
                         "key 'model.materials.aluminium.poissons_ratio'"),
        "bolt-direction-zero": (dump(set_at(FE_BOX, "model.bolts[0].direction", [0.0, 0.0, 0.0])),
                                "key 'model.bolts[0].direction'"),
        "modes-count-zero": (dump(set_at(FE_BOX, "analysis.modes.count", 0)), "key 'analysis.modes.count'"),
    }
    for name, (body, text) in cases.items():
        write_case(f"syntax-{name}", body, text)
    # bytes that are not text at all
    path = os.path.join(OUT, "syntax-binary-junk.yaml")
    with open(path, "wb") as f:
        f.write(b"# expect: exit=2 command=run text=binary-junk.yaml\n" + bytes(range(256)) * 2)
    ENTRIES.append("syntax-binary-junk")


def csv_cases():
    """Fit targets: the case names measured.csv; each entry gets its own CSV and case."""
    lines = MEASURED.splitlines()
    header, rows = lines[0], lines[1:]
    variants = {
        "empty": ("", ": key 'fit.targets[0].file': the target file is empty"),
        "header-only": (header + "\n", "key 'fit.targets[0].file'"),
        "no-amplitude": (header.replace("amplitude", "amp", 1) + "\n" + "\n".join(rows) + "\n",
                         ":1:1: key 'fit.targets[0].file'"),
        "text-value": (header + "\n" + rows[0].replace("31.81348302", "abc") + "\n" + "\n".join(rows[1:]) + "\n",
                       ":2:"),
        "nan-value": (header + "\n" + rows[0].replace("31.81348302", "nan") + "\n" + "\n".join(rows[1:]) + "\n",
                      ":2:"),
        "negative-damping": (header + "\n" + rows[0].replace("0.001701355161", "-0.0017") + "\n"
                             + "\n".join(rows[1:]) + "\n", ":2:"),
        "zero-sigma": (header + "\n" + rows[0].replace("0.06363", "0") + "\n" + "\n".join(rows[1:]) + "\n", ":2:"),
        "short-row": (header + "\n" + ",".join(rows[0].split(",")[:3]) + "\n" + "\n".join(rows[1:]) + "\n", ":2:"),
        "long-row": (header + "\n" + rows[0] + ",7\n" + "\n".join(rows[1:]) + "\n", ":2:"),
        "amplitude-outside": (header + "\n" + rows[0].replace("8.783711456e-07", "1.0") + "\n"
                              + "\n".join(rows[1:]) + "\n", ":2:"),
        "inf-value": (header + "\n" + rows[0].replace("31.81348302", "inf") + "\n" + "\n".join(rows[1:]) + "\n",
                      ":2:"),
        "duplicate-column": (header + ",amplitude\n" + "\n".join(r + ",1e-6" for r in rows) + "\n",
                             ":1:"),
        "binary": (b"\x00\x01\x02amplitude\xff\xfe\n\x00\x00\n", "key 'fit.targets[0].file'"),
    }
    for name, (content, text) in variants.items():
        csv_name = f"csv-{name}.csv"
        tree = copy.deepcopy(FIT)
        tree["fit"]["targets"][0]["file"] = csv_name
        write_case(f"csv-{name}", tree, f"{csv_name}{text}" if text.startswith(":") else text,
                   command="fit", extra_files=[(csv_name, content)])
    tree = copy.deepcopy(FIT)
    tree["fit"]["targets"][0]["file"] = "csv-no-such-file.csv"
    write_case("csv-missing-file", tree, "key 'fit.targets[0].file'", command="fit")


def mesh_cases():
    inp_lines = INP.splitlines(keepends=True)
    msh_lines = MSH.splitlines(keepends=True)
    inp_variants = {
        "no-elements": ("".join(inp_lines[:13]), "no elements"),
        "missing-node": (INP.replace("1, 1, 2, 5, 4, 7, 8, 11, 10", "1, 1, 2, 5, 4, 7, 8, 11, 99"), "99"),
        "text-coordinate": (INP.replace("2, 0.01, 0.0, 0.0", "2, x, 0.0, 0.0"), ".inp:3:"),
        "unknown-element": (INP.replace("TYPE=C3D8,", "TYPE=S4R,"), ".inp:14:"),
        "duplicate-node": (INP.replace("3, 0.02, 0.0, 0.0", "2, 0.02, 0.0, 0.0"), ".inp:4:"),
        "short-element": (INP.replace("2, 2, 3, 6, 5, 8, 9, 12, 11", "2, 2, 3, 6, 5"), ".inp:16:"),
        "empty": ("", "no elements"),
        "binary": (bytes(range(256)), ".inp"),
        "node-system": (INP.replace("*NODE", "*NODE, SYSTEM=C", 1), ".inp:1:"),
        "inverted-element": (INP.replace("1, 1, 2, 5, 4, 7, 8, 11, 10", "1, 7, 8, 11, 10, 1, 2, 5, 4"), "element 1"),
    }
    msh_variants = {
        "version-2": (MSH.replace("4.1 0 8", "2.2 0 8", 1), ".msh:2:"),
        "binary-flag": (MSH.replace("4.1 0 8", "4.1 1 8", 1), ".msh:2:"),
        "no-format": ("".join(msh_lines[3:]), ".msh:1:"),
        "truncated": ("".join(msh_lines[:20]), ".msh"),
        "count-too-high": (MSH.replace(f"1 {len(NODES)} 1 {len(NODES)}\n3 1 0 {len(NODES)}",
                                       f"1 {len(NODES) + 5} 1 {len(NODES) + 5}\n3 1 0 {len(NODES) + 5}", 1), ".msh"),
        "text-coordinate": (MSH.replace("0.01 0.0 0.0\n", "0.01 abc 0.0\n", 1), ".msh:"),
        "unknown-element-type": (MSH.replace(f"3 1 5 {len(HEXES)}", f"3 1 99 {len(HEXES)}", 1), ".msh:"),
        "missing-node": (MSH.replace("1 1 2 5 4 7 8 11 10", "1 1 2 5 4 7 8 11 99", 1), ".msh"),
        "empty": ("", ".msh"),
        "binary": (bytes(range(256)), ".msh"),
        "no-end-nodes": (MSH.replace("$EndNodes\n", "", 1), ".msh"),
    }
    for ext, variants in (("inp", inp_variants), ("msh", msh_variants)):
        for name, (content, text) in variants.items():
            mesh = f"mesh-{ext}-{name}.{ext}"
            tree = copy.deepcopy(FE_MESH)
            tree["model"]["parts"][0]["mesh"] = mesh
            write_case(f"mesh-{ext}-{name}", tree, f"mesh-{ext}-{name}{text}" if text.startswith(".") else text,
                       extra_files=[(mesh, content)])
    # the valid meshes themselves (run_corpus.py checks that they are accepted)
    with open(os.path.join(HERE, "valid.inp"), "w") as f:
        f.write(INP)
    with open(os.path.join(HERE, "valid.msh"), "w") as f:
        f.write(MSH)
    for ext in ("inp", "msh"):
        tree = copy.deepcopy(FE_MESH)
        tree["model"]["parts"][0]["mesh"] = f"valid.{ext}"
        with open(os.path.join(HERE, f"valid_{ext}.yaml"), "w") as f:
            f.write(dump(tree))


CLI_LINES = [
    # exit, text the one error line must contain, arguments
    (2, "option '--amplitude'", "loop --amplitude -1"),
    (2, "option '--amplitude'", "loop --amplitude abc"),
    (2, "option '--amplitude'", "loop --amplitude nan"),
    (2, "option '--amplitude'", "loop --amplitude 1e160"),
    (2, "option '--amplitude'", "loop --amplitude 1e-5 --normal-force 1e120"),
    (2, "option '--n'", "loop --n 1"),
    (2, "option '--n'", "loop --n 0"),
    (2, "option '--n'", "loop --n -0.5"),
    (2, "option '--mu'", "loop --mu 0"),
    (2, "option '--mu'", "loop --mu inf"),
    (2, "option '--normal-force'", "loop --normal-force -1"),
    (2, "option '--kt0'", "loop --kt0 0"),
    (2, "option '--time-samples'", "loop --time-samples 3"),
    (2, "option '--time-samples'", "loop --time-samples 99999999999"),
    (2, "option '--time-samples'", "loop --time-samples 1.5"),
    (2, "option '--law'", "loop --law coulomb"),
    (2, "option '--harmonic'", "loop --harmonic 0,1e-6"),
    (2, "option '--harmonic'", "loop --harmonic 200,1e-6"),
    (2, "option '--harmonic'", "loop --harmonic 3"),
    (2, "option '--harmonic'", "loop --harmonic 3,abc"),
    (2, "option '--lambda'", "loop --normal-amplitude 1e-6"),
    (2, "option '--lambda'", "loop --lambda -1"),
    (2, "option '--normal-amplitude'", "loop --normal-amplitude nan --lambda 1e6"),
    (2, "not expected: --no-such-option", "loop --no-such-option"),
    (2, "jointhb: ", "no-such-command"),
    (2, "cannot open case file", "run tests/corpus/no-such-case.yaml"),
    (2, "--no-cache", "run tests/corpus/valid_inp.yaml --no-cache --cache-dir /tmp/x"),
    (2, "not expected: b.yaml", "run a.yaml b.yaml"),
    (2, "case is required", "fit"),
    (2, "cannot open case file", "fit tests/corpus/no-such-case.yaml"),
]


def main():
    if os.path.isdir(OUT):
        shutil.rmtree(OUT)
    os.makedirs(OUT)
    yaml_cases()
    syntax_cases()
    csv_cases()
    mesh_cases()
    with open(os.path.join(HERE, "cli_lines.txt"), "w") as f:
        f.write("# exit<TAB>text the error line must contain<TAB>arguments (run from the source tree)\n")
        for code, text, args in CLI_LINES:
            f.write(f"{code}\t{text}\t{args}\n")
    print(f"{len(ENTRIES)} case entries and {len(CLI_LINES)} command lines in {os.path.relpath(OUT)}")


if __name__ == "__main__":
    sys.exit(main())
