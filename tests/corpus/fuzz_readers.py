#!/usr/bin/python3
"""Seeded mutation fuzzing of jointhb's readers: YAML case files, Abaqus .inp and Gmsh .msh meshes,
and fit target CSVs.

    fuzz_readers.py JOINTHB [--count N] [--seed S] [--seconds T] [--keep DIR] [--replay DIR]

Each input is a valid seed (tests/corpus/valid_*.yaml with its mesh, cases 02, 03 and 01, and a
fit case with its CSV) with 1–4 random text mutations (numbers replaced by extremes, lines deleted,
duplicated or swapped, bytes inserted, special characters, indentation changed, truncation) in one
of its files. `jointhb run --check` must then either accept it (exit 0, one line "…: valid") or
refuse it as bad input (exit 2, exactly one printable line "jointhb run: …" without "nan"), within
20 s and without a signal. Everything is determined by the seed: CI runs a fixed count. The inputs
are made first, in order, and checked by --jobs processes at a time (the answers, reported in input
order, do not depend on it: each check is its own process on its own folder).

Failing inputs are written to --keep DIR (one folder each, with the command to reproduce); the
ones found so far, fixed, are kept in tests/corpus/fuzz/ and replayed with --replay.
"""
import argparse
import concurrent.futures
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SOURCE = os.path.dirname(os.path.dirname(HERE))
NAN = re.compile(r"(?<![A-Za-z0-9_-])nan(?![A-Za-z0-9_-])", re.IGNORECASE)
NUMBER = re.compile(r"(?<![A-Za-z_])[-+]?\d+(\.\d*)?([eE][-+]?\d+)?")
EXTREMES = ["0", "-1", "1e308", "-1e308", "1e-320", "nan", "inf", "-inf", ".nan", ".inf",
            "99999999999999999999", "3.5", "", "0x10", "1e400", "-0"]
SPECIALS = list(":[]{},-#&*!|>'\"%@`\t\n\\") + ["\x00", "\x1b", "\xc3\xa9", "\ufeff", "\r\n"]


def seeds():
    """(name, {file name: text}, case file name) of every seed input."""
    out = []
    with open(os.path.join(HERE, "valid_inp.yaml")) as f:
        yaml_inp = f.read()
    with open(os.path.join(HERE, "valid_msh.yaml")) as f:
        yaml_msh = f.read()
    with open(os.path.join(HERE, "valid.inp")) as f:
        inp = f.read()
    with open(os.path.join(HERE, "valid.msh")) as f:
        msh = f.read()
    out.append(("inp", {"case.yaml": yaml_inp.replace("valid.inp", "mesh.inp"), "mesh.inp": inp}, "mesh.inp"))
    out.append(("msh", {"case.yaml": yaml_msh.replace("valid.msh", "mesh.msh"), "mesh.msh": msh}, "mesh.msh"))
    for case in ("01-contact-loop", "02-two-dof-frf", "03-one-dof-gaul-mayer"):
        with open(os.path.join(SOURCE, "cases", case, "case.yaml")) as f:
            out.append(("yaml-" + case[:2], {"case.yaml": f.read()}, "case.yaml"))
    with open(os.path.join(SOURCE, "cases", "10-fit-one-dof", "case.yaml")) as f:
        fit = f.read()
    with open(os.path.join(SOURCE, "cases", "10-fit-one-dof", "measured_backbone.csv")) as f:
        csv = f.read()
    out.append(("csv", {"case.yaml": fit, "measured_backbone.csv": csv}, "measured_backbone.csv"))
    out.append(("yaml-10", {"case.yaml": fit, "measured_backbone.csv": csv}, "case.yaml"))
    return out


def mutate(text, rng):
    lines = text.split("\n")
    kind = rng.randrange(8)
    if kind == 0:
        numbers = list(NUMBER.finditer(text))
        if numbers:
            m = rng.choice(numbers)
            return text[:m.start()] + rng.choice(EXTREMES) + text[m.end():]
    if kind == 1 and len(lines) > 1:
        del lines[rng.randrange(len(lines))]
        return "\n".join(lines)
    if kind == 2:
        i = rng.randrange(len(lines))
        lines.insert(i, lines[i])
        return "\n".join(lines)
    if kind == 3 and len(lines) > 1:
        i, j = rng.randrange(len(lines)), rng.randrange(len(lines))
        lines[i], lines[j] = lines[j], lines[i]
        return "\n".join(lines)
    if kind == 4:
        i = rng.randrange(len(text) + 1)
        junk = "".join(chr(rng.randrange(256)) for _ in range(rng.randrange(1, 8)))
        return text[:i] + junk + text[i:]
    if kind == 5 and text:
        return text[:rng.randrange(len(text))]
    if kind == 6 and text:
        i = rng.randrange(len(text))
        return text[:i] + rng.choice(SPECIALS) + text[i + 1:]
    i = rng.randrange(len(lines))
    lines[i] = (" " * rng.randrange(1, 4) + lines[i]) if rng.random() < 0.5 else lines[i].lstrip()
    return "\n".join(lines)


def judge(code, err):
    """Why the reaction is wrong (empty when right)."""
    if code is None:
        return "no answer within 20 s"
    if code < 0:
        return f"killed by signal {-code}"
    try:
        text = err.decode("utf-8")
    except UnicodeDecodeError:
        return "stderr is not UTF-8"
    lines = text.splitlines()
    if code == 0:
        return "" if len(lines) == 1 and lines[0].endswith(": valid") else f"exit 0 with stderr {text[:200]!r}"
    if code != 2:
        return f"exit {code} (expected 0 or 2)"
    if len(lines) != 1:
        return f"{len(lines)} lines on stderr"
    line = lines[0]
    if not line.startswith("jointhb run: "):
        return "no 'jointhb run: ' prefix"
    if any(ord(c) < 32 or ord(c) == 127 for c in line):
        return "control characters in the message"
    if NAN.search(line):
        return "nan in the message"
    return ""


def check(program, folder):
    try:
        p = subprocess.run([program, "run", "--check", "case.yaml"], cwd=folder, capture_output=True,
                           timeout=20)
    except subprocess.TimeoutExpired:
        return None, b""
    return p.returncode, p.stderr


def write(folder, files):
    os.makedirs(folder, exist_ok=True)
    for name, text in files.items():
        with open(os.path.join(folder, name), "wb") as f:
            f.write(text.encode("utf-8", "surrogateescape") if isinstance(text, str) else text)


def replay(program, directory, jobs):
    names = sorted(n for n in os.listdir(directory) if os.path.isdir(os.path.join(directory, n)))
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        answers = list(pool.map(lambda n: check(program, os.path.join(directory, n)), names))
    failures = 0
    for name, (code, err) in zip(names, answers):
        why = judge(code, err)
        if why:
            failures += 1
            print(f"FAIL: {name}: {why}: {err.decode('utf-8', 'replace').strip()[:300]}")
    print(f"replayed {len(names)} kept fuzz inputs, {failures} failure(s)")
    return failures


def mutated_inputs(base, rng, count):
    """The `count` mutated inputs of the seed: (seed name, files, target) in order."""
    out = []
    for _ in range(count):
        name, files, target = rng.choice(base)
        files = dict(files)
        text = files[target]
        for _ in range(rng.randint(1, 4)):
            text = mutate(text, rng)
        files[target] = text
        out.append((name, files))
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("program")
    parser.add_argument("--count", type=int, default=400)
    parser.add_argument("--seed", type=int, default=20261126)
    parser.add_argument("--seconds", type=float, default=600.0, help="stop early after this long")
    parser.add_argument("--jobs", type=int, default=2, help="checks run at a time")
    parser.add_argument("--keep", help="write failing inputs here")
    parser.add_argument("--replay", help="also replay the kept inputs in this directory")
    args = parser.parse_args()
    if args.jobs < 1:
        parser.error(f"--jobs must be >= 1, got {args.jobs}")
    program = os.path.abspath(args.program)
    failures = replay(program, args.replay, args.jobs) if args.replay else 0
    inputs = mutated_inputs(seeds(), random.Random(args.seed), args.count)
    start = time.monotonic()
    reactions = {0: 0, 2: 0}
    done = 0
    with tempfile.TemporaryDirectory(prefix="jointhb-fuzz-") as work:

        def run_one(i):
            if time.monotonic() - start > args.seconds:
                return None  # past the time bound: not run
            folder = os.path.join(work, f"{i:05d}")
            write(folder, inputs[i][1])
            return check(program, folder)

        with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
            answers = list(pool.map(run_one, range(len(inputs))))
        for i, answer in enumerate(answers):
            if answer is None:
                continue
            code, err = answer
            name = inputs[i][0]
            folder = os.path.join(work, f"{i:05d}")
            done += 1
            if code in reactions:
                reactions[code] += 1
            why = judge(code, err)
            if why:
                failures += 1
                print(f"FAIL: input {i} ({name}, seed {args.seed}): {why}: "
                      f"{err.decode('utf-8', 'replace').strip()[:300]}")
                if args.keep:
                    kept = os.path.join(args.keep, f"{name}-{args.seed}-{i:05d}")
                    shutil.rmtree(kept, ignore_errors=True)
                    shutil.copytree(folder, kept)
            shutil.rmtree(folder)
    print(f"{done} mutated inputs in {time.monotonic() - start:.1f} s: {reactions[0]} accepted, "
          f"{reactions[2]} refused, {failures} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
