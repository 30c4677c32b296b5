#!/usr/bin/env python3
"""Reports source files and functions over the size limits of the solver's code.

    check_sizes.py [--repo DIR] [--max-file 650] [--max-function 120] [FOLDER ...]

Files are counted in lines; a function from its signature to its closing brace. Functions are
found by their braces: a block opened after a closing parenthesis (or `) const` and the like)
that is not a control statement or a lambda. Default folders: native/, openscad_export/,
step_export/ (and bench/). Exit status 0 when everything is within the limits, 1 otherwise.
"""
import argparse
import re
import sys

from source_tree import REPO, report, sources

CONTROL = re.compile(r"\b(if|for|while|switch|catch|else|do)\b[^;]*$")
SIGNATURE_END = re.compile(r"\)\s*(const)?\s*(noexcept)?\s*(override)?\s*(->\s*[\w:<>,\s*&]+)?\s*\{\s*$")


def strip(line):
    """The line without // comments and string literals (braces in them do not count)."""
    line = re.sub(r'"(\\.|[^"\\])*"', '""', line)
    line = re.sub(r"'(\\.|[^'\\])*'", "''", line)
    return line.split("//", 1)[0]


def functions(lines):
    """(name line, first line, last line) of every function body in the file."""
    found = []
    depth = 0
    open_at = []  # (depth before, start line, is function)
    for n, raw in enumerate(lines):
        line = strip(raw)
        for i, ch in enumerate(line):
            if ch == "{":
                head = line[: i + 1]
                is_fn = bool(SIGNATURE_END.search(head)) and not CONTROL.search(head) \
                    and "](" not in head and "] (" not in head and not head.lstrip().startswith("[")
                start = n
                if is_fn:
                    # The signature may start some lines above (parameters wrapped).
                    k = n
                    while k > 0 and "(" not in strip(lines[k]).split(")")[0] and k > n - 8:
                        k -= 1
                    start = k
                open_at.append((depth, start, is_fn))
                depth += 1
            elif ch == "}":
                depth -= 1
                if open_at:
                    d, start, is_fn = open_at.pop()
                    if is_fn and not any(f for _, _, f in open_at):
                        found.append((start, n))
    return found


def problems_of(rel, lines, max_file, max_function):
    found = []
    if len(lines) > max_file:
        found.append(f"{rel}: {len(lines)} lines (limit {max_file})")
    for start, end in functions(lines):
        length = end - start + 1
        if length > max_function:
            found.append(f"{rel}:{start + 1}: a function of {length} lines "
                         f"(limit {max_function}): {lines[start].strip()[:70]}")
    return found


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("dirs", nargs="*", default=["native", "openscad_export", "step_export", "bench"])
    parser.add_argument("--repo", default=REPO, help="the source tree (default: this one)")
    parser.add_argument("--max-file", type=int, default=650)
    parser.add_argument("--max-function", type=int, default=120)
    args = parser.parse_args()
    problems = []
    for rel, text in sources(args.repo, args.dirs):
        problems += problems_of(rel, text.splitlines(), args.max_file, args.max_function)
    return report("sizes", problems, "over the limits")

if __name__ == "__main__":
    sys.exit(main())
