"""Shared pieces of the Python module's tests: the repository, the CLI binary of the same build tree (the tests
compare the module's values with the files the CLI writes), the default scene, and the CLI's number formats."""
import os
import subprocess
from pathlib import Path

import pytest

import geartopo

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "scenes" / "skmc1200w-mn14-z35.yaml"
TRUTH = ROOT / "scenes" / "truth-skmc1200w-mn14-z35.yaml"
MEASURED = ROOT / "scenes" / "demo" / "measured.csv"


def cli_path():
    return os.environ.get("GEARTOPO_CLI", str(ROOT / "build" / "bin" / "geartopo"))


def run_cli(*args, expect=0):
    """Runs the CLI (quiet); returns the completed process. `expect`: the exit code it must give."""
    proc = subprocess.run([cli_path(), *map(str, args), "--quiet"], capture_output=True, text=True, cwd=ROOT)
    assert proc.returncode == expect, f"geartopo {' '.join(map(str, args))}: exit {proc.returncode}\n{proc.stderr}"
    return proc


@pytest.fixture(scope="session")
def scene():
    return geartopo.load_scene(SCENE)


@pytest.fixture(scope="session")
def truth():
    return geartopo.load_scene(TRUTH)


def topology_lines(t):
    """topology.csv's lines (grinding/topology_csv.cpp's formats) from the module's columns."""
    return [f"{t['tooth'][i]},{t['flank'][i]},{t['row'][i]},{t['col'][i]},{t['diameter_mm'][i]:.6f},"
            f"{t['z_mm'][i]:.6f},{t['deviation_um'][i]:.4f},{t['design_um'][i]:.4f}" for i in range(len(t["tooth"]))]


def traces_lines(t):
    """traces.csv's lines from the module's columns."""
    return [f"{t['tooth'][i]},{t['flank'][i]},{t['trace'][i]},{t['roll_length_mm'][i]:.6f},{t['diameter_mm'][i]:.6f},"
            f"{t['z_mm'][i]:.6f},{t['deviation_um'][i]:.4f},{t['design_um'][i]:.4f}" for i in range(len(t["tooth"]))]


def file_lines(path):
    """A CSV file's data lines (header left out)."""
    return Path(path).read_text().splitlines()[1:]
