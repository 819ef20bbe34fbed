#!/usr/bin/env python3
"""The dependency rule of docs/architecture.md, checked on every product file.

docs/architecture.md's table "Who may include whom" is the one home of the
rule: each row names a folder, what its library may include and what its
command files (*_command.cc) may include besides. This script reads that table
and fails, naming file:line, on any `#include "folder/..."` of a project
folder the row does not allow. A folder always includes itself; a subfolder
with a row of its own is a folder of its own (generator/lang is not generator).

  include_rules.py ROOT            check the tree at ROOT
  include_rules.py ROOT --planted  check that a planted wrong include fails
"""
import os
import re
import shutil
import sys
import tempfile

TABLE_TITLE = "### Who may include whom"
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def read_rules(root):
    """{folder: (library may include, command files may include)} from the doc."""
    text = open(os.path.join(root, "docs", "architecture.md"), encoding="utf-8").read()
    if TABLE_TITLE not in text:
        sys.exit("docs/architecture.md: no section '%s'" % TABLE_TITLE)
    section = text.split(TABLE_TITLE, 1)[1].split("\n#", 1)[0]
    rows = {}
    aliases = {}
    for line in section.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) < 3 or not cells[0].startswith("`"):
            continue
        folder = cells[0].strip("`")
        library = re.findall(r"`([^`]+)`", cells[1])
        commands = re.findall(r"`([^`]+)`", cells[2])
        rows[folder] = (library, commands)
    # "core" names the shared core: every libs/ folder with a row.
    aliases["core"] = [f for f in rows if f.startswith("libs/")]

    def expand(names):
        out = []
        for n in names:
            out.extend(aliases.get(n, [n]))
        return set(out)

    return {f: (expand(lib), expand(cmd)) for f, (lib, cmd) in rows.items()}


def folder_of(path, folders):
    """The longest folder with a row that holds `path`."""
    best = None
    for f in folders:
        if path.startswith(f + "/") and (best is None or len(f) > len(best)):
            best = f
    return best


def violations(root):
    rules = read_rules(root)
    found = []
    checked = 0
    for folder in sorted(rules):
        for dirpath, _, files in os.walk(os.path.join(root, folder)):
            for name in sorted(files):
                if not name.endswith((".h", ".cc")):
                    continue
                path = os.path.relpath(os.path.join(dirpath, name), root)
                if folder_of(path, rules) != folder:
                    continue  # a subfolder with its own row
                checked += 1
                library, commands = rules[folder]
                allowed = {folder} | library
                if name.endswith("_command.cc"):
                    allowed |= commands
                text = open(os.path.join(root, path), encoding="utf-8", errors="replace").read()
                for match in INCLUDE.finditer(text):
                    target = folder_of(match.group(1), rules)
                    if target is None or target in allowed:
                        continue
                    line = text.count("\n", 0, match.start()) + 1
                    found.append("%s:%d: includes %s, but %s may include only %s" %
                                 (path, line, match.group(1), folder,
                                  ", ".join(sorted(allowed - {folder})) or "itself"))
    return checked, found


def main():
    root = sys.argv[1]
    if "--planted" in sys.argv:
        # A copy of the product folders with one include the table forbids
        # (the core reaching up into a feature): the check must name it.
        with tempfile.TemporaryDirectory() as tmp:
            for folder in list(read_rules(root)) + ["docs"]:
                top = folder.split("/")[0]
                if not os.path.exists(os.path.join(tmp, top)):
                    shutil.copytree(os.path.join(root, top), os.path.join(tmp, top),
                                    ignore=shutil.ignore_patterns("build"))
            planted = os.path.join(tmp, "libs", "util", "error.h")
            with open(planted, "a", encoding="utf-8") as f:
                f.write('\n#include "report/report.h"\n')
            _, found = violations(tmp)
            expected = [v for v in found if v.startswith("libs/util/error.h:") and "report/report.h" in v]
            if len(found) != 1 or len(expected) != 1:
                print("FAIL: the planted include gave %r" % found)
                return 1
            print("the planted include is found: " + found[0])
            return 0
    checked, found = violations(root)
    for v in found:
        print(v)
    print("%d files checked, %d includes outside the rule" % (checked, len(found)))
    return 1 if found or checked == 0 else 0


if __name__ == "__main__":
    sys.exit(main())
