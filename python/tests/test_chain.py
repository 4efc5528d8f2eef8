"""Scenes on other kinematic chains (issue 42: scenes/cafxzy-mn14-z35.yaml, the CAFXZY preset, and
scenes/cxfzay-mn14-z35.yaml, the CXFZAY): the module simulates and evaluates them with the values of the CLI's files,
the chain's errors reach the flanks, compensation corrects in the chain's own axes, and the diagnosis names a hidden
error of one of its axes."""
import json

import numpy as np

import geartopo
from conftest import ROOT, file_lines, run_cli, topology_lines

CAFXZY = ROOT / "scenes" / "cafxzy-mn14-z35.yaml"
CXFZAY = ROOT / "scenes" / "cxfzay-mn14-z35.yaml"


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


def with_constants(path, constants, tmp_path):
    """The scene at `path` with its machine constants replaced by `constants` (a YAML flow map), written to tmp_path."""
    text = path.read_text()
    start, end = text.index("  constants:"), text.index("\nwheel:")
    scene_file = tmp_path / ("constants_" + path.name)
    scene_file.write_text(text[:start] + "  constants: " + constants + "\n" + text[end:])
    return scene_file


def test_a_cxfzay_scene_simulates_and_evaluates_as_the_cli_does(tmp_path):
    scene = geartopo.load_scene(CXFZAY)
    run_cli("simulate", CXFZAY, "--out", tmp_path / "sim", "--teeth", "1,18", "--method", "linear")
    topo = geartopo.simulate(scene, teeth=[1, 18], method="linear")
    assert topology_lines(topo) == file_lines(tmp_path / "sim" / "topology.csv")
    assert 0.1 < np.abs(topo["deviation_um"]).max() < 100.0
    run_cli("evaluate", CXFZAY, "--out", tmp_path / "eval", "--method", "linear")
    with open(tmp_path / "eval" / "iso1328.json") as f:
        cli = json.load(f)["before"]
    assert geartopo.evaluate(scene, method="linear") == cli


def test_a_cxfzay_scene_is_compensated_in_its_own_axes(tmp_path):
    # A constant z-straightness of the radial X table (8 µm) lifts the gear along its axis; the Z column moves the
    # wheel along the same z with no rotary axis between: ΔZ = +8 µm at every row, X, Y, A, C untouched
    # (tests/app: CliChain.CompensateCorrectsConstantErrorsOfTheCxfzayInItsOwnAxes has the A swivel's zero as well).
    r = geartopo.compensate(geartopo.load_scene(with_constants(CXFZAY, "{delta_zx_um: 8}", tmp_path)), step_mm=10,
                            samples=0)
    c = r["corrections"]
    assert len(c["space"]) > 70
    assert np.allclose(c["dZ_um"], 8.0, atol=0.01)
    for key in ("dX_um", "dY_um", "dA_urad", "dC_urad"):
        assert np.abs(c[key]).max() < 0.01, key
    assert np.allclose(c["A_deg"], -30.0, atol=1e-6)  # the chain's A: α = −β on this tool-side swivel
    assert np.allclose(c["Y_mm"], 120.0 * np.tan(np.radians(30.0)), atol=1e-5)  # Y = y − 120·tan α, y = 0
    assert all(c["within_strokes"])


def test_a_hidden_roll_of_the_cxfzays_radial_table_is_diagnosed(tmp_path):
    # ε_xx 60 µrad in a truth scene, four teeth measured by the CLI's synth; the module's diagnosis on the shipped
    # scene names it in its class with its size, as the CLI's (CliChain.DiagnoseNamesAHiddenRollOfTheCxfzaysRadialTable).
    text = CXFZAY.read_text()
    anchor = "(ISO 230-7), representative\n"
    at = text.index(anchor) + len(anchor)
    truth = tmp_path / "truth.yaml"
    truth.write_text(text[:at] + "    epsilon_xx_urad: 60\n" + text[at:])
    measured = tmp_path / "m.csv"
    run_cli("synth", truth, "--out", measured, "--teeth", "1,10,18,27", "--noise-um", "0.3", "--seed", "3")
    d = geartopo.diagnose(geartopo.load_scene(CXFZAY), str(measured), noise_um=0.3)
    chosen = d["chosen"]
    assert chosen is not None, d["verdict"]
    change = chosen["machine_changes"][0]
    listed = json.dumps(chosen.get("equivalent", [])) + json.dumps(chosen.get("look_alikes", []))
    assert change["component"] == "epsilon_xx" or "epsilon_xx" in listed, chosen
    assert abs(abs(change["change_urad"]) - 60.0) < 2.0 * change["uncertainty"] + 1.0, chosen


CFUZBY = """  chain:
    name: CFUZBY
    workpiece:
      - {name: C, kind: rotary, direction: [0, 0, 1]}
    tool:
      - {name: U, kind: linear, direction: [1, 0, 0], stroke_mm: [0, 900]}
      - {name: Z, kind: linear, direction: [0, 0, 1], stroke_mm: [0, 800]}
      - {name: B, kind: rotary, direction: [1, 0, 0], stroke_deg: [-45, 45]}
      - {name: Y, kind: linear, direction: [0, 1, 0], stroke_mm: [-200, 200]}
"""


def test_corrections_are_named_by_a_chain_with_other_letters_as_the_cli_names_them(tmp_path):
    # The CFXZAY's geometry with the radial slide called U and the swivel B: pose order Y, Z, U, B, C. A constant
    # positioning error of U (8 µm) is undone by U alone; the columns carry the chain's letters, as corrections.csv.
    text = with_constants(CXFZAY, "{delta_xu_um: 8}", tmp_path).read_text()
    start = text.index("  chain: CXFZAY")
    scene_file = tmp_path / "cfuzby.yaml"
    scene_file.write_text(text[:start] + CFUZBY + text[text.index("\n", start) + 1:])
    c = geartopo.compensate(geartopo.load_scene(scene_file), step_mm=10, samples=0)["corrections"]
    # corrections.csv's header for this chain (CorrectionTable::write_csv; tests/compensation check its letters).
    header = ["space", "z_stroke_mm", "time_s", "Y_mm", "Z_mm", "U_mm", "B_deg", "C_deg", "dY_um", "dZ_um",
              "dU_um", "dB_urad", "dC_urad", "within_strokes"]
    # The CLI writes the same rows, and its cycle table too: the fold's stroke axis is the one along the gear axis (Z,
    # pose slot Y), not pose slot Z (U), so U is the lead axis, carrying its −8 µm per pose, and Y the set-up axis.
    run_cli("compensate", scene_file, "--out", tmp_path / "cli", "--step", "10", "--samples", "0")
    lines = (tmp_path / "cli" / "corrections.csv").read_text().splitlines()
    assert lines[0] == ",".join(header)
    assert len(lines) - 1 == len(c["space"])
    cli_du = np.array([float(line.split(",")[10]) for line in lines[1:]])
    assert np.allclose(cli_du, c["dU_um"], atol=5e-5)  # the CLI's 4 decimals
    cycle = [line for line in (tmp_path / "cli" / "cycle_corrections.csv").read_text().splitlines()
             if not line.startswith("#")]
    assert cycle[0] == "space,index_dC_urad,Z_mm,lead_dU_um,lead_dC_urad"
    lead_du = np.array([float(line.split(",")[3]) for line in cycle[1:]])
    assert len(lead_du) >= 70 and np.allclose(lead_du, -8.0, atol=0.01)
    assert list(c.keys()) == header
    assert np.allclose(c["dU_um"], -8.0, atol=0.01)
    for key in ("dY_um", "dZ_um", "dB_urad", "dC_urad"):
        assert np.abs(c[key]).max() < 0.01, key
