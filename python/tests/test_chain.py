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


def test_a_cafxzy_scene_is_compensated_in_its_own_axes_as_the_cli_does(tmp_path):
    # A constant A-table zero error of 100 µrad alone: undone by the A axis alone, ΔA = −100 µrad at every row (the
    # table turns to A + E_AOA wherever it is commanded), X, Y, Z, C untouched — the chain's own axes, as the CLI's
    # corrections.csv (tests/app: CliChain.CompensateCorrectsConstantErrorsOfTheCafxzyInItsOwnAxes).
    text = CAFXZY.read_text()
    start, end = text.index("  constants:"), text.index("\nwheel:")
    scene_file = tmp_path / "s.yaml"
    scene_file.write_text(text[:start] + "  constants: {E_AOA_urad: 100}\n" + text[end:])
    r = geartopo.compensate(geartopo.load_scene(scene_file), step_mm=10, samples=0)
    c = r["corrections"]
    assert len(c["space"]) > 70
    assert np.allclose(c["dA_urad"], -100.0, atol=0.01)
    for key in ("dX_um", "dY_um", "dZ_um", "dC_urad"):
        assert np.abs(c[key]).max() < 0.01, key
    assert np.allclose(np.abs(c["A_deg"]), 30.0, atol=1e-6)  # the chain's A: the cross angle, the gear's helix angle
    assert all(c["within_strokes"])
    run_cli("compensate", scene_file, "--out", tmp_path / "cli", "--step", "10", "--samples", "0")
    lines = (tmp_path / "cli" / "corrections.csv").read_text().splitlines()
    assert lines[0] == ("space,z_stroke_mm,time_s,X_mm,Y_mm,Z_mm,A_deg,C_deg,dX_um,dY_um,dZ_um,dA_urad,dC_urad,"
                        "within_strokes")
    assert len(lines) - 1 == len(c["space"])
