#!/usr/bin/env python3
"""Checks that the solver's stages include only themselves and earlier stages.

The data flow runs model < eval < features < refine < seed < optimise < search < pipeline < io
(docs/ARCHITECTURE.md), all above the few headers directly in native/include/csgfit/ (the
error type). A header or source of one stage (native/include/csgfit/STAGE/ and
native/src/STAGE/) that includes a header of a later stage is reported, and so is any solver
file that includes the writers (openscad_export/, step_export/) or the front ends.
Exit status 0 when the layering holds, 1 otherwise.
"""
import os
import re
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BASE = "base"  # error.h: what every stage may throw
STAGES = [BASE, "model", "eval", "features", "refine", "seed", "optimise", "search", "pipeline", "io"]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
WRITERS = ("scad_", "step_")


def stage_of_file(rel):
    parts = rel.split(os.sep)
    if parts[:3] == ["native", "include", "csgfit"] and len(parts) == 4:
        return BASE
    if parts[:3] == ["native", "include", "csgfit"] and len(parts) > 4:
        return parts[3]
    if parts[:2] == ["native", "src"] and len(parts) > 3:
        return parts[2]
    return None


def stage_of_include(path):
    parts = path.split("/")
    if parts[0] == "csgfit" and len(parts) > 2:
        return parts[1]
    if parts[0] in STAGES and len(parts) > 1:
        return parts[0]
    return None


def main():
    problems = []
    for root in ("native/include/csgfit", "native/src"):
        for folder, _, files in os.walk(os.path.join(REPO, root)):
            for name in sorted(files):
                if not name.endswith((".h", ".cpp")):
                    continue
                rel = os.path.relpath(os.path.join(folder, name), REPO)
                own = stage_of_file(rel)
                if own not in STAGES:
                    problems.append(f"{rel}: not in a stage folder")
                    continue
                with open(os.path.join(REPO, rel)) as f:
                    text = f.read()
                for inc in INCLUDE.findall(text):
                    if os.path.basename(inc).startswith(WRITERS):
                        problems.append(f"{rel}: includes the writer {inc}")
                        continue
                    other = stage_of_include(inc)
                    if other in STAGES and STAGES.index(other) > STAGES.index(own):
                        problems.append(f"{rel} ({own}) includes {inc} ({other}), a later stage")
    for p in problems:
        print("layers:", p)
    print(f"layers: {'ok' if not problems else str(len(problems)) + ' problem(s)'}")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
