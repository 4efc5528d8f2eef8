"""evaluate(): the ISO 1328-1 values of `geartopo evaluate`'s iso1328.json, exactly."""
import json

import pytest

import geartopo
from conftest import SCENE, run_cli


@pytest.fixture(scope="module")
def cli_iso(tmp_path_factory):
    out = tmp_path_factory.mktemp("evaluate")
    run_cli("evaluate", SCENE, "--out", out)
    return json.loads((out / "iso1328.json").read_text())


def test_evaluate_equals_iso1328_json(scene, cli_iso):
    assert geartopo.evaluate(scene) == cli_iso["before"]


def test_evaluate_of_simulate_arrays_equals_iso1328_json(scene, cli_iso):
    topo = geartopo.simulate(scene, teeth="all")
    assert geartopo.evaluate(scene, topo) == cli_iso["before"]


def test_evaluate_of_a_traces_file_equals_the_cli(scene, tmp_path):
    run_cli("synth", SCENE, "--out", tmp_path / "traces.csv", "--format", "traces", "--teeth", "all", "--noise-um", "0.2")
    run_cli("evaluate", SCENE, "--traces", tmp_path / "traces.csv", "--out", tmp_path / "eval", "--iso-direction", "normal")
    cli = json.loads((tmp_path / "eval" / "iso1328.json").read_text())
    assert geartopo.evaluate(scene, str(tmp_path / "traces.csv"), iso_direction="normal") == cli["before"]
    # The same traces as arrays (synth's, same seed, every digit where the file keeps 4 decimals): the same values
    # within the file's rounding (5e-5 µm a point).
    traces = geartopo.synth(scene, teeth="all", noise_um=0.2, format="traces")
    close_to(geartopo.evaluate(scene, traces, iso_direction="normal"), cli["before"], 1e-3)


def close_to(a, b, tol_um):
    """Every number of a within tol_um of b's, every other value equal, the same keys and lengths."""
    if isinstance(a, dict):
        assert a.keys() == b.keys()
        for k in a:
            close_to(a[k], b[k], tol_um)
    elif isinstance(a, list):
        assert len(a) == len(b)
        for x, y in zip(a, b):
            close_to(x, y, tol_um)
    elif isinstance(a, float) and isinstance(b, (int, float)):
        assert a == pytest.approx(b, abs=tol_um)
    else:
        assert a == b
