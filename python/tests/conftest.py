"""Shared fixtures: the built `iilfm` program and one simulated scan detected by it."""

import json
import os
import subprocess
from pathlib import Path

import pytest

SOURCE_DIR = Path(os.environ.get("IILFM_SOURCE_DIR", Path(__file__).resolve().parents[2]))
CLI = os.environ.get("IILFM_CLI", str(SOURCE_DIR / "build" / "bin" / "iilfm"))


def run_cli(*args, check=True):
    """Runs the `iilfm` program; returns the CompletedProcess (text mode)."""
    done = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True)
    if check and done.returncode != 0:
        raise AssertionError(f"iilfm {' '.join(map(str, args))} failed: {done.stderr}")
    return done


def cli_error(*args):
    """The one-line message `iilfm` prints for bad input, without its "iilfm: " prefix."""
    done = run_cli(*args, check=False)
    assert done.returncode == 2, done
    line = done.stderr.strip()
    assert line.startswith("iilfm: "), line
    return line[len("iilfm: "):]


@pytest.fixture(scope="session")
def scan(tmp_path_factory):
    """A simulated Mid-40 scan of the 7 x 5 tag grid, its map, and the CLI's JSON result."""
    d = tmp_path_factory.mktemp("scan")
    pcd, marker_map, out = d / "grid.pcd", d / "grid_map.yaml", d / "cli.json"
    run_cli("sim", "--scene", "grid", "--frames", "20", "--seed", "3", "--out", pcd, "--map",
            marker_map)
    run_cli("detect", pcd, "--sensor", "mid40", "--map", marker_map, "--json", out, "-q")
    return {"pcd": str(pcd), "map": str(marker_map), "json": json.loads(out.read_text()),
            "dir": d}
