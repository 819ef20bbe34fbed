#!/usr/bin/env python3
"""Every link of the user documentation leads somewhere (ctest docs_links).

Checks README.md, CHANGELOG.md, bench/README.md and docs/*.md:
- a Markdown link `[text](target)` to a relative path names a file or folder that exists;
- a link with `#anchor` (to another page or within the page) names a heading of that page, with
  the anchors GitHub gives headings (lower case, punctuation dropped, spaces as hyphens, `-N` for
  the N-th repeat);
- a `docs/<page>.md` or `bench/README.md` named in the text of those pages, or in a comment of the
  sources (C++, CMake, Python, shell), exists, and a section cited after it in quotes
  (`docs/format.md, "Oriented boxes"`, or `format.md "Camera rigs"` between pages) is named in
  that page (a heading, a bold lead or its text).

Usage: docs_links.py SOURCE_DIR. Exit 0 when every link resolves, 1 with one line per broken link
(file:line: target).
"""
import os
import pathlib
import re
import sys

PAGES = ["README.md", "CHANGELOG.md", "bench/README.md", "fuzz/README.md"]
SOURCE_SUFFIXES = {".cc", ".h", ".py", ".sh", ".cmake", ".txt", ".json", ".lcap", ".lscene"}
# Every folder of the checkout is scanned (so a moved folder stays covered) except these.
SKIPPED_DIRS = {".git", "build", "demo", "golden", "__pycache__", "corpus"}
LINK = re.compile(r"\[(?:[^\]\[]|\[[^\]]*\])*\]\(([^)\s]+)\)")
NAMED = re.compile(r"\b((?:docs/[A-Za-z0-9_.-]+|[a-z]+/README)\.md)\b")
# A page named with the sections it cites: docs/languages.md, "Requirements and quotas", "Rigs".
CITED = re.compile(r'(?<![\w/.-])((?:docs/)?[A-Za-z0-9_-]+\.md)(?:[,:]\s*|\s+)\(?((?:"[^"\n]{1,80}"(?:,\s*|\s+and\s+|\s+)?)+)')
COMMENT_BREAK = re.compile(r"\n\s*(?://|#|\*)?\s*")
FENCE = re.compile(r"^\s*(```|~~~)")


def slug(heading):
    """GitHub's anchor of a heading's text."""
    text = re.sub(r"<[^>]+>", "", heading).strip().lower()
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(path, cache={}):
    if path not in cache:
        seen = {}
        found = set()
        in_fence = False
        for line in path.read_text(encoding="utf-8").splitlines():
            if FENCE.match(line):
                in_fence = not in_fence
                continue
            m = None if in_fence else re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
            if m:
                base = slug(m.group(1))
                n = seen.get(base, 0)
                seen[base] = n + 1
                found.add(base if n == 0 else f"{base}-{n}")
        cache[path] = found
    return cache[path]


def check_page(root, page, problems):
    in_fence = False
    for number, line in enumerate(page.read_text(encoding="utf-8").splitlines(), 1):
        if FENCE.match(line):
            in_fence = not in_fence
            continue
        where = f"{page.relative_to(root)}:{number}"
        if not in_fence:
            for target in LINK.findall(line):
                if re.match(r"^[a-z][a-z0-9+.-]*:", target):  # http:, https:, mailto:
                    continue
                file_part, _, anchor = target.partition("#")
                dest = (page.parent / file_part).resolve() if file_part else page
                if not dest.exists():
                    problems.append(f"{where}: link to a missing file: {target}")
                elif anchor and dest.suffix == ".md" and anchor not in anchors(dest):
                    problems.append(f"{where}: link to a missing heading: {target}")
        for name in NAMED.findall(line):
            if not (root / name).exists():
                problems.append(f"{where}: names a missing page: {name}")


def check_citations(root, path, text, problems):
    """Sections cited in quotes after a page name are named in that page (comments may wrap)."""
    flat = COMMENT_BREAK.sub(" ", text)
    for m in CITED.finditer(flat):
        # docs/<page>.md, or <page>.md of docs/ (as the pages name each other) or of the root.
        page = next((p for p in (root / m.group(1), root / "docs" / m.group(1)) if p.exists()), None)
        if page is None:
            continue  # a missing docs/ page is reported by check_page and check_sources
        words = page.read_text(encoding="utf-8").lower().replace("`", "")
        for section in re.findall(r'"([^"]+)"', m.group(2)):
            if section.lower().replace("`", "") not in words:
                problems.append(f"{path.relative_to(root)}: cites a section {m.group(1)} does not "
                                f"have: \"{section}\"")


def check_sources(root, problems):
    for folder, dirs, files in os.walk(root):
        dirs[:] = sorted(d for d in dirs if d not in SKIPPED_DIRS and not d.startswith("build"))
        for name in sorted(files):
            path = pathlib.Path(folder) / name
            if path.suffix not in SOURCE_SUFFIXES:
                continue
            text = path.read_text(encoding="utf-8", errors="replace")
            check_citations(root, path, text, problems)
            for number, line in enumerate(text.splitlines(), 1):
                for page in NAMED.findall(line):
                    if not (root / page).exists():
                        problems.append(f"{path.relative_to(root)}:{number}: "
                                        f"names a missing page: {page}")


def main():
    if len(sys.argv) != 2:
        print(__doc__)
        return 2
    root = pathlib.Path(sys.argv[1]).resolve()
    pages = [root / p for p in PAGES if (root / p).exists()] + sorted((root / "docs").glob("*.md"))
    problems = []
    for page in pages:
        check_page(root, page, problems)
        check_citations(root, page, page.read_text(encoding="utf-8"), problems)
    check_sources(root, problems)
    for problem in problems:
        print(problem)
    print(f"docs_links: {len(pages)} pages, {len(problems)} broken link(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
