#!/usr/bin/python3
"""Runs the bad-input corpus (generate_corpus.py) against the jointhb program.

    run_corpus.py JOINTHB [SOURCE_DIR]

Every entry must be refused as bad input: the expected exit code (2), exactly one line on stderr,
starting with the command's prefix and containing the text that names the defect, printable
ASCII, no "nan", no summary.json in the output directory, no signal. The valid meshes next to the
corpus must be accepted (exit 0). Prints one line per failure and a count; exits 1 on any failure.
"""
import os
import re
import subprocess
import sys
import tempfile

NAN = re.compile(r"(?<![A-Za-z0-9_-])nan(?![A-Za-z0-9_-])", re.IGNORECASE)
TIMEOUT = 120  # s per entry: a refused input takes milliseconds; a run that was not refused more


def run(program, args, cwd):
    try:
        p = subprocess.run([program] + args, cwd=cwd, capture_output=True, timeout=TIMEOUT)
    except subprocess.TimeoutExpired:
        return None, b"", b""
    return p.returncode, p.stdout, p.stderr


def check(name, expect_exit, command, text, code, err, out_dir):
    """The reasons an entry fails (empty when it passes)."""
    problems = []
    if code is None:
        return [f"not refused within {TIMEOUT} s"]
    if code < 0:
        problems.append(f"killed by signal {-code}")
    if code != expect_exit:
        problems.append(f"exit {code}, expected {expect_exit}")
    try:
        message = err.decode("utf-8")
    except UnicodeDecodeError:
        problems.append("stderr is not UTF-8")
        message = err.decode("utf-8", "replace")
    lines = message.splitlines()
    if len(lines) != 1:
        problems.append(f"{len(lines)} lines on stderr, expected 1")
    line = lines[-1] if lines else ""
    if any(ord(c) < 32 or ord(c) == 127 for c in line):
        problems.append("control characters in the message")
    prefix = f"jointhb {command}: " if command else "jointhb"
    if not line.startswith(prefix):
        problems.append(f"does not start with '{prefix}'")
    if text not in line:
        problems.append(f"does not contain '{text}'")
    if NAN.search(line.replace(name, "")):
        problems.append("contains nan")
    if out_dir and os.path.exists(os.path.join(out_dir, "summary.json")):
        problems.append("a refused input wrote summary.json")
    if problems:
        problems.append(f"message: {line[:300]}")
    return problems


def main():
    program = os.path.abspath(sys.argv[1])
    source = os.path.abspath(sys.argv[2]) if len(sys.argv) > 2 else \
        os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    corpus = os.path.join(source, "tests", "corpus")
    bad = os.path.join(corpus, "bad")
    failures, entries = [], 0
    with tempfile.TemporaryDirectory(prefix="jointhb-corpus-") as work:
        for file_name in sorted(os.listdir(bad)):
            if not file_name.endswith(".yaml"):
                continue
            path = os.path.join(bad, file_name)
            with open(path, "rb") as f:
                first = f.readline().decode("utf-8", "replace").strip()
            m = re.match(r"# expect: exit=(\d+) command=(\w+) text=(.*)$", first)
            if not m:
                failures.append(f"{file_name}: no '# expect:' line")
                continue
            expect_exit, command, text = int(m.group(1)), m.group(2), m.group(3)
            out_dir = os.path.join(work, file_name[:-5])
            code, _, err = run(program, [command, path, "-o", out_dir], cwd=work)
            entries += 1
            for p in check(file_name, expect_exit, command, text, code, err, out_dir):
                failures.append(f"{file_name}: {p}")
        with open(os.path.join(corpus, "cli_lines.txt")) as f:
            for number, line in enumerate(f, 1):
                if line.startswith("#") or not line.strip():
                    continue
                expect_exit, text, args = line.rstrip("\n").split("\t")
                argv = args.split()
                # Errors of the command-line parser itself come before any command: "jointhb: ".
                command = argv[0] if argv[0] in ("run", "fit", "loop") else ""
                if text.startswith("not expected") or text.endswith("is required"):
                    command = ""
                code, _, err = run(program, argv, cwd=source)
                entries += 1
                for p in check(f"cli_lines.txt:{number}", int(expect_exit), command, text, code, err, None):
                    failures.append(f"cli_lines.txt:{number} ({args}): {p}")
        for valid in ("valid_inp.yaml", "valid_msh.yaml"):
            code, _, err = run(program, ["run", os.path.join(corpus, valid), "-o",
                                         os.path.join(work, valid[:-5])], cwd=work)
            entries += 1
            if code != 0:
                failures.append(f"{valid}: the valid mesh was not accepted (exit {code}): "
                                f"{err.decode('utf-8', 'replace').strip()[-300:]}")
    for f in failures:
        print("FAIL:", f)
    print(f"{entries} corpus entries, {len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
