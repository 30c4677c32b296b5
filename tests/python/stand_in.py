"""A benchmark driver run end to end with a stand-in for the csgfit CLI (the judges' tests)."""

import json
import os
import subprocess
import sys

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def run_driver(tmp_path, cli_text, driver, args):
    """Writes `cli_text` as an executable csgfit, runs scripts/`driver` with it and `args` into
    tmp_path/out; returns the finished process and out/results.json (None when missing)."""
    cli = tmp_path / "csgfit"
    cli.write_text(cli_text)
    cli.chmod(0o755)
    out = tmp_path / "out"
    proc = subprocess.run([sys.executable, os.path.join(REPO, "scripts", driver), "--cli",
                           str(cli), "--out", str(out)] + list(args),
                          capture_output=True, text=True, timeout=600)
    results = out / "results.json"
    return proc, json.loads(results.read_text()) if results.exists() else None
