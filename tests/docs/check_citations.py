#!/usr/bin/python3
"""Every document and every equation tag the project cites exists in the repository.

Run by ctest as `docs.citations` with the source directory as argument. It reads the project's
text files (src/, include/, tests/, docs/, validation/, cases/, README.md, CMakeLists.txt) and
reports, one line each as FILE:LINE: problem,

- a cited Markdown file (`docs/x.md`, `theory.md`, `README_convergence.md`, `../docs/cli.md`)
  that exists neither relative to the citing file, nor to the repository's root, nor in docs/;
- a citation of a file outside the repository (`../shared/...`, a path climbing above the root);
- an equation tag cited in a family this script knows (`T-31`, `eq. (B-4)`, `(N-1)`) that the
  document defining the family does not define. A tag is defined where it stands in parentheses
  at the end of a line or of a heading of that document, e.g. `... = 0   (T-17)`.

Tags of families N and P are also ordinary arithmetic (`i = 0..N-1`, `p = 0..P-1`): they count as
citations only in parentheses or after "eq."/"eqs."/"equation". Other families are cited bare too
(`the harmonic preconditioner of T-32c`).
"""
import re
import sys
from pathlib import Path

# Family -> the documents that define its tags (docs/ relative).
FAMILIES = {
    "T": ["theory.md"],
    "TI": ["time-integration.md"],
    "TIE": ["ties.md"],
    "B": ["bolts-and-preload.md"],
    "L": ["bolts-and-preload.md"],
    "P": ["bolts-and-preload.md"],
    "CB": ["reduction.md"],
    "M": ["zero-thickness-elements.md"],
    "N": ["zero-thickness-elements.md"],
}
ARITHMETIC = {"N", "P"}  # also written as N-1, P-1 in index ranges

SCANNED_DIRS = ["src", "include", "tests", "docs", "validation", "cases"]
SCANNED_FILES = ["README.md", "CMakeLists.txt"]
SUFFIXES = {".cpp", ".hpp", ".h", ".py", ".sh", ".inc", ".md", ".yaml", ".txt", ".in", ".cmake"}

FAMILY = "|".join(sorted(FAMILIES, key=len, reverse=True))
TAG = r"(?P<tag>(?P<family>" + FAMILY + r")-(?P<number>\d+[a-z]?))"
# A tag not glued to a longer word or number (TIE-1 is not I-1, T-31 is not T-310, 9-T-1 no).
BARE_TAG = re.compile(r"(?<![\w.-])" + TAG + r"(?![\w-])")
PAREN_TAG = re.compile(r"\(" + TAG + r"\)")
EQ_TAG = re.compile(r"\b(?:eqs?\.\s*|equations?\s+)\(?" + TAG + r"(?![\w-])")
DEFINITION = re.compile(r"\(" + TAG + r"\)[.,;:]?\s*$|^\s*\(" + TAG.replace("?P<", "?P<start_") + r"\)")
# A Markdown file name, possibly with a relative path; not part of a URL.
DOC = re.compile(r"(?<![\w/:.-])((?:\.\./|\./)*(?:[\w.-]+/)*[\w.-]*[A-Za-z0-9_]\.md)\b")
OUTSIDE = re.compile(r"\.\./shared\b|/work/shared\b")
# A document cited by its name and a section: "NUMERICS §3" (read as NUMERICS.md), also across a
# line break of a comment ("(NUMERICS\n  /// §3)").
SECTION_OF = re.compile(r"\b([A-Z][A-Z_]{2,})(?:\.md)?(?:\s*\n\s*(?://+|#)?)?\s+§")


def defined_tags(root):
    tags = {}
    for family, docs in FAMILIES.items():
        found = set()
        for doc in docs:
            for line in (root / "docs" / doc).read_text(encoding="utf-8").splitlines():
                m = DEFINITION.search(line.rstrip())
                if m and family in (m.group("family"), m.group("start_family")):
                    found.add(m.group("tag") or m.group("start_tag"))
                # A heading names the tag it defines: "### 2.1 Exact integration (T-1)".
                if line.startswith("#"):
                    for h in PAREN_TAG.finditer(line):
                        if h.group("family") == family:
                            found.add(h.group("tag"))
        tags[family] = found
    return tags


def scanned_files(root):
    for name in SCANNED_FILES:
        if (root / name).is_file():
            yield root / name
    for d in SCANNED_DIRS:
        for path in sorted((root / d).rglob("*")):
            if path.is_file() and path.suffix in SUFFIXES and "results" not in path.parts:
                yield path


def cited_tags(line):
    seen = {}
    for pattern in (PAREN_TAG, EQ_TAG):
        for m in pattern.finditer(line):
            seen[m.start("tag")] = (m.group("family"), m.group("tag"))
    for m in BARE_TAG.finditer(line):
        if m.group("family") not in ARITHMETIC:
            seen.setdefault(m.start("tag"), (m.group("family"), m.group("tag")))
    return seen.values()


def main():
    root = Path(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).resolve().parents[2]).resolve()
    this = Path(__file__).resolve()
    tags = defined_tags(root)
    problems = []
    for path in scanned_files(root):
        if path.resolve() == this:
            continue  # its docstring shows the patterns it looks for
        rel = path.relative_to(root)
        text = path.read_text(encoding="utf-8", errors="replace")
        sections = {}  # line number -> documents cited there by name and section
        for m in SECTION_OF.finditer(text):
            sections.setdefault(text.count("\n", 0, m.start()) + 1, []).append(m.group(1) + ".md")
        for number, line in enumerate(text.splitlines(), 1):
            where = f"{rel}:{number}"
            if OUTSIDE.search(line):
                problems.append(f"{where}: cites a file outside the repository: {line.strip()}")
            cited_docs = [m.group(1) for m in DOC.finditer(line)]
            cited_docs += [d for d in sections.get(number, []) if d not in cited_docs]
            for cited in cited_docs:
                candidates = [path.parent / cited, root / cited, root / "docs" / cited]
                if "/" not in cited:  # a bare name: wherever it is (README_epmc.md of validation/hb)
                    candidates += sorted(root.glob("*/**/" + cited))
                inside = [c for c in candidates if c.resolve().is_relative_to(root)]
                if not inside:
                    problems.append(f"{where}: '{cited}' is outside the repository")
                elif not any(c.is_file() for c in inside):
                    problems.append(f"{where}: cites '{cited}', which is not in the repository")
            for family, tag in cited_tags(line):
                if tag not in tags[family]:
                    docs = ", ".join("docs/" + d for d in FAMILIES[family])
                    problems.append(f"{where}: cites {tag}, which {docs} does not define")
    for p in problems:
        print(p)
    defined = sum(len(t) for t in tags.values())
    if problems:
        print(f"{len(problems)} citation(s) of missing documents or equation tags", file=sys.stderr)
        return 1
    print(f"ok: every cited document exists; every cited tag is among the {defined} defined")
    return 0


if __name__ == "__main__":
    sys.exit(main())
