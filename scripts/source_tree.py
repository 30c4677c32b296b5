"""What the source checks (check_layers.py, check_sizes.py) share: the C++ files of a tree and
the one-line report each check ends with."""
import os

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SOURCES = (".h", ".cpp")


def sources(repo, roots):
    """(path relative to repo, text) of every C++ source below the given folders, sorted."""
    for root in roots:
        for folder, dirs, files in os.walk(os.path.join(repo, root)):
            dirs.sort()
            for name in sorted(files):
                if name.endswith(SOURCES):
                    path = os.path.join(folder, name)
                    with open(path, errors="replace") as f:
                        yield os.path.relpath(path, repo), f.read()


def report(tag, problems, what):
    """Prints each problem and a last line (`TAG: ok` or the count); returns the exit status."""
    for p in problems:
        print(f"{tag}: {p}")
    print(f"{tag}: {'ok' if not problems else f'{len(problems)} {what}'}")
    return 1 if problems else 0
