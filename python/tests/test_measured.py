"""compare, diagnose, plan and synth: the content of `geartopo compare/diagnose/plan/synth`'s files, exactly, with the
measurement as a file or as arrays."""
import csv
import json

import numpy as np
import pytest

import geartopo
from conftest import MEASURED, SCENE, TRUTH, file_lines, run_cli, topology_lines

MEASURED_ARG = "scenes/demo/measured.csv"  # as the CLI is given it (the JSON files record the argument)
SCENE_ARG = "scenes/skmc1200w-mn14-z35.yaml"


def residual_lines(r):
    """residuals.csv's lines (report/measurement_report.cpp's formats) from the module's columns."""
    return [f"{r['tooth'][i]},{r['flank'][i]},{r['row'][i]},{r['col'][i]},{r['diameter_mm'][i]:.6f},{r['z_mm'][i]:.6f},"
            f"{r['measured_um'][i]:.4f},{r['model_um'][i]:.4f},{r['residual_um'][i]:.4f},{r['source_line'][i]},"
            f"{r['point_id'][i]},{r['design_um'][i]:.4f}" for i in range(len(r["tooth"]))]


@pytest.fixture(scope="module")
def rel_scene(monkeypatch_module):
    return geartopo.load_scene(SCENE_ARG)


@pytest.fixture(scope="module")
def monkeypatch_module():
    mp = pytest.MonkeyPatch()
    mp.chdir(SCENE.parents[1])  # the repository: relative paths as the CLI is given them
    yield mp
    mp.undo()


def measured_arrays():
    """The demo measurement read with the csv module: a dict of numpy arrays."""
    with open(MEASURED) as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    out = {k: np.array([r[k] for r in rows]) for k in rows[0]}
    for k in ("tooth", "row", "col"):
        out[k] = out[k].astype(np.int32)
    for k in ("diameter_mm", "z_mm", "deviation_um", "design_um"):
        if k in out:
            out[k] = out[k].astype(np.float64)
    return out


def test_compare_equals_compare_json_and_residuals_csv(rel_scene, tmp_path):
    run_cli("compare", SCENE_ARG, "--measured", MEASURED_ARG, "--out", tmp_path)
    c = geartopo.compare(rel_scene, MEASURED_ARG)
    residuals = c.pop("residuals")
    assert c == json.loads((tmp_path / "compare.json").read_text())
    assert residual_lines(residuals) == file_lines(tmp_path / "residuals.csv")


def test_compare_of_arrays_equals_compare_of_the_file(scene):
    from_file = geartopo.compare(scene, str(MEASURED))
    from_arrays = geartopo.compare(scene, measured_arrays())
    assert from_arrays["measured"] == "measured arrays"
    for key in ("overall", "flanks", "noise_um", "failing_regions", "tooth_to_tooth"):
        assert from_arrays[key] == from_file[key]
    for key in ("measured_um", "model_um", "residual_um", "diameter_mm"):
        np.testing.assert_array_equal(from_arrays["residuals"][key], from_file["residuals"][key])


def test_diagnose_equals_diagnosis_json_and_the_completed_scene(rel_scene, tmp_path):
    run_cli("diagnose", SCENE_ARG, "--measured", MEASURED_ARG, "--out", tmp_path)
    d = geartopo.diagnose(rel_scene, MEASURED_ARG, yaml_dir=tmp_path)
    yaml = d.pop("scene_with_effect_yaml")
    assert d == json.loads((tmp_path / "diagnosis.json").read_text())
    assert yaml == (tmp_path / "scene_with_effect.yaml").read_text()
    assert "thermal_drift" in yaml


def test_diagnose_reports_progress_and_refuses_unknown_candidates(scene):
    reports = []
    geartopo.diagnose(scene, str(MEASURED), candidates=["thermal_drift"], progress=lambda d, t: reports.append((d, t)))
    assert reports and reports[-1][0] == reports[-1][1]
    with pytest.raises(ValueError, match="candidates: 'warp_drive' is not an effect of the library"):
        geartopo.diagnose(scene, str(MEASURED), candidates=["warp_drive"])


def test_plan_equals_plan_json(rel_scene, tmp_path):
    run_cli("plan", SCENE_ARG, "--measured", MEASURED_ARG, "--out", tmp_path)
    assert geartopo.plan(rel_scene, MEASURED_ARG) == json.loads((tmp_path / "plan.json").read_text())


@pytest.mark.parametrize("extra", [[], ["--stroke-scatter"]])
def test_synth_equals_the_cli_measurement(truth, tmp_path, extra):
    run_cli("synth", TRUTH, "--out", tmp_path / "m.csv", "--teeth", "1,18", "--noise-um", "0.5", "--seed", "7", *extra)
    m = geartopo.synth(truth, teeth=[1, 18], noise_um=0.5, seed=7, stroke_scatter=bool(extra))
    assert topology_lines(m) == file_lines(tmp_path / "m.csv")


def test_the_demo_measurement_is_synth_of_the_truth(truth):
    """scenes/demo/measured.csv is `geartopo synth TRUTH --teeth 1,18 --noise-um 0.5 --seed 7` (the scene says so)."""
    # The file was written before the design_um column (0 on this scene's bare involute).
    lines = topology_lines(geartopo.synth(truth, seed=7))
    assert all(l.endswith(",0.0000") for l in lines)
    assert [l.rsplit(",", 1)[0] for l in lines] == file_lines(MEASURED)


def test_synth_arrays_are_a_measurement(scene, truth):
    """synth()'s arrays go straight into compare: the file of the same measurement keeps 4 decimals (5e-5 µm)."""
    c = geartopo.compare(scene, geartopo.synth(truth, seed=7), noise_um=0.5)
    f = geartopo.compare(scene, str(MEASURED), noise_um=0.5)
    assert c["overall"]["rms_um"] == pytest.approx(f["overall"]["rms_um"], abs=1e-4)
    np.testing.assert_allclose(c["residuals"]["residual_um"], f["residuals"]["residual_um"], rtol=0, atol=1e-4)
