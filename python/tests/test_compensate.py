"""compensate(): the corrections, the gear before and after and the predicted distribution of `geartopo compensate`'s
files, exactly."""
import json

import numpy as np
import pytest

import geartopo
from conftest import SCENE, file_lines, run_cli, topology_lines, traces_lines

SAMPLES = 6  # enough to exercise the prediction; its statistics are the Monte Carlo tests' business


def correction_lines(c):
    """corrections.csv's lines (compensation/correction_table.cpp's formats) from the module's columns."""
    return [f"{c['space'][i]},{c['z_stroke_mm'][i]:.4f},{c['time_s'][i]:.3f},{c['X_mm'][i]:.5f},{c['Y_mm'][i]:.5f},"
            f"{c['Z_mm'][i]:.5f},{c['A_deg'][i]:.7f},{c['C_deg'][i]:.7f},{c['dX_um'][i]:.4f},{c['dY_um'][i]:.4f},"
            f"{c['dZ_um'][i]:.4f},{c['dA_urad'][i]:.4f},{c['dC_urad'][i]:.4f},{'yes' if c['within_strokes'][i] else 'no'}"
            for i in range(len(c["space"]))]


@pytest.fixture(scope="module")
def both(scene, tmp_path_factory):
    out = tmp_path_factory.mktemp("compensate")
    run_cli("compensate", SCENE, "--out", out, "--samples", SAMPLES, "--seed", 3)
    reports = []
    result = geartopo.compensate(scene, samples=SAMPLES, seed=3, progress=lambda d, t: reports.append((d, t)))
    return out, result, reports


def test_corrections_equal_corrections_csv(both):
    out, r, _ = both
    assert correction_lines(r["corrections"]) == file_lines(out / "corrections.csv")
    assert r["corrections"]["within_strokes"].dtype == np.bool_


def test_before_and_after_equal_the_topology_files(both):
    out, r, _ = both
    assert topology_lines(r["before"]) == file_lines(out / "topology_before.csv")
    assert topology_lines(r["nominal_after"]) == file_lines(out / "topology_after.csv")
    assert traces_lines(r["before"]["traces"]) == file_lines(out / "traces_before.csv")


def test_iso_values_and_prediction_equal_iso1328_json(both):
    out, r, reports = both
    j = json.loads((out / "iso1328.json").read_text())
    assert r["iso1328"]["before"] == j["before"]
    assert r["iso1328"]["nominal_after"] == j["nominal_after"]
    assert r["largest_abs_deviation_um"] == j["largest_abs_deviation_um"]
    assert r["prediction"] == j["prediction"] == json.loads((out / "prediction.json").read_text())
    assert r["improvement"] == j["improvement"]
    assert reports[-1] == (SAMPLES, SAMPLES)


def test_without_samples_there_is_no_prediction(scene):
    r = geartopo.compensate(scene, samples=0, method="paper")
    assert r["prediction"] is None and r["improvement"] is None
