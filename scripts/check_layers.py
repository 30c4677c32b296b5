#!/usr/bin/env python3
"""Checks that the solver's stages include only themselves and earlier stages.

The data flow runs model < eval < features < refine < seed < optimise < construct < search <
pipeline < io
(docs/ARCHITECTURE.md), all above the few headers directly in native/include/csgfit/ (the
error type). A header or source of one stage (native/include/csgfit/STAGE/ and
native/src/STAGE/) that includes a header of a later stage is reported, and so is any solver
file that includes the writers (openscad_export/, step_export/) or the front ends.

    check_layers.py [--repo DIR]

Exit status 0 when the layering holds, 1 otherwise.
"""
import argparse
import os
import re
import sys

from source_tree import REPO, report, sources

BASE = "base"  # error.h: what every stage may throw
STAGES = [BASE, "model", "eval", "features", "refine", "seed", "optimise", "construct", "search", "pipeline", "io"]
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


def problems_of(rel, text):
    """What one file breaks: its stage, or includes of writers or of later stages."""
    own = stage_of_file(rel)
    if own not in STAGES:
        return [f"{rel}: not in a stage folder"]
    found = []
    for inc in INCLUDE.findall(text):
        other = stage_of_include(inc)
        if os.path.basename(inc).startswith(WRITERS):
            found.append(f"{rel}: includes the writer {inc}")
        elif other in STAGES and STAGES.index(other) > STAGES.index(own):
            found.append(f"{rel} ({own}) includes {inc} ({other}), a later stage")
    return found


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repo", default=REPO, help="the source tree (default: this one)")
    args = parser.parse_args()
    problems = []
    for rel, text in sources(args.repo, ("native/include/csgfit", "native/src")):
        problems += problems_of(rel, text)
    return report("layers", problems, "problem(s)")

if __name__ == "__main__":
    sys.exit(main())
