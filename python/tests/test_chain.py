"""A scene on another kinematic chain (issue 42: scenes/cafxzy-mn14-z35.yaml, the CAFXZY preset): the module
simulates and evaluates it with the values of the CLI's files, and the chain's errors do reach the flanks."""
import json

import numpy as np

import geartopo
from conftest import ROOT, file_lines, run_cli, topology_lines

CAFXZY = ROOT / "scenes" / "cafxzy-mn14-z35.yaml"


def test_a_cafxzy_scene_simulates_as_the_cli_does(tmp_path):
    scene = geartopo.load_scene(CAFXZY)
    run_cli("simulate", CAFXZY, "--out", tmp_path, "--teeth", "1,18", "--method", "linear")
    topo = geartopo.simulate(scene, teeth=[1, 18], method="linear")
    assert topology_lines(topo) == file_lines(tmp_path / "topology.csv")
    # Its squareness and axis-line constants (tens of µrad, a few µm) leave µm on the flanks, not nothing.
    assert 0.1 < np.abs(topo["deviation_um"]).max() < 100.0


def test_a_cafxzy_scene_evaluates_as_the_cli_does(tmp_path):
    scene = geartopo.load_scene(CAFXZY)
    run_cli("evaluate", CAFXZY, "--out", tmp_path, "--method", "linear")
    with open(tmp_path / "iso1328.json") as f:
        cli = json.load(f)["before"]
    assert len(cli["flanks"]) == 70
    assert geartopo.evaluate(scene, method="linear") == cli
