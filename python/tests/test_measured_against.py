"""measured_against (docs/modifications.md, "Measurements against the design"): a crowned gear ground as drawn and
written without its design_um column, as a measuring machine that evaluates against the drawing writes it. Said, the
file is the file with its column; not said, compare and diagnose raise the doubt with the CLI's numbers and evaluate
warns; said for a file that has the column, refused naming the keyword. The reference is the file WITH its column."""
import json

import pytest

import geartopo
from conftest import ROOT, run_cli

CROWNED = ROOT / "scenes" / "skmc1200w-mn14-z35-crowned.yaml"


def without_design_column(src, dst):
    lines = src.read_text().splitlines()
    dst.write_text("\n".join(l if not l or l.startswith("#") else l.rsplit(",", 1)[0] for l in lines) + "\n")


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("against")
    run_cli("synth", CROWNED, "--out", d / "with.csv", "--teeth", "1,18", "--noise-um", "0.5", "--seed", "4")
    run_cli("synth", CROWNED, "--out", d / "traces_with.csv", "--format", "traces", "--teeth", "all", "--noise-um", "0",
            "--seed", "4")
    without_design_column(d / "with.csv", d / "without.csv")
    without_design_column(d / "traces_with.csv", d / "traces_without.csv")
    return d


@pytest.fixture(scope="module")
def crowned():
    return geartopo.load_scene(CROWNED)


def test_compare_and_diagnose_as_the_file_with_its_column_once_said(crowned, files):
    ref = geartopo.compare(crowned, str(files / "with.csv"), noise_um=0.5)
    said = geartopo.compare(crowned, str(files / "without.csv"), noise_um=0.5, measured_against="design")
    assert said["reference_in_doubt"] is None
    assert said["overall"]["rms_um"] == pytest.approx(ref["overall"]["rms_um"], abs=1e-4)  # the file's 4 decimals
    d = geartopo.diagnose(crowned, str(files / "without.csv"), noise_um=0.5, measured_against="design")
    assert d["chosen"] is None, d["verdict"]


def test_not_said_the_doubt_is_raised_as_by_the_cli(crowned, files, tmp_path):
    c = geartopo.compare(crowned, str(files / "without.csv"), noise_um=0.5)
    assert c["reference_in_doubt"] is not None
    assert c["reference_in_doubt"]["sentence"].startswith("The measurement looks evaluated against the drawing")
    run_cli("compare", CROWNED, "--measured", files / "without.csv", "--out", tmp_path / "c", "--noise-um", "0.5")
    cli = json.loads((tmp_path / "c" / "compare.json").read_text())
    assert c["reference_in_doubt"] == cli["reference_in_doubt"]
    d = geartopo.diagnose(crowned, str(files / "without.csv"), noise_um=0.5)
    assert any(r["reason"] == "reference_in_doubt" for r in d["decisions"])


def test_evaluate_a_traces_file_said_against_the_drawing(crowned, files):
    ref = geartopo.evaluate(crowned, str(files / "traces_with.csv"))
    said = geartopo.evaluate(crowned, str(files / "traces_without.csv"), measured_against="design")
    for a, b in zip(ref["flanks"], said["flanks"]):
        assert b["F_alpha_um"] == pytest.approx(a["F_alpha_um"], abs=0.02)
        assert b["f_Hbeta_um"] == pytest.approx(a["f_Hbeta_um"], abs=0.02)
    with pytest.warns(UserWarning, match="no design_um column"):
        unsaid = geartopo.evaluate(crowned, str(files / "traces_without.csv"))
    assert unsaid["flanks"][0]["F_alpha_um"] > ref["flanks"][0]["F_alpha_um"] + 4.0  # the drawing's C_α and tip relief


def test_refused_naming_the_keyword(crowned, files):
    with pytest.raises(geartopo.InputError, match="design_um"):
        geartopo.compare(crowned, str(files / "with.csv"), noise_um=0.5, measured_against="design")
    with pytest.raises(ValueError, match='^measured_against: "drawing" is not'):
        geartopo.compare(crowned, str(files / "without.csv"), noise_um=0.5, measured_against="drawing")
    with pytest.raises(TypeError, match="^measured_against: "):
        geartopo.diagnose(crowned, str(files / "without.csv"), noise_um=0.5, measured_against=1)
    with pytest.raises(ValueError, match="^measured_against: is for a measured traces file"):
        geartopo.evaluate(crowned, measured_against="design")
