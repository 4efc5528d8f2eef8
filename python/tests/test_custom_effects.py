"""A scene's own physics (custom_effects, docs/tutorial.md section 8) from Python: the declared law is simulated by
synth and fitted by diagnose as the CLI does it, and named as the user's with its expression."""
import json

import pytest

import geartopo
from conftest import ROOT, run_cli

EXAMPLES = ROOT / "docs" / "examples"
TEETH = [1, 6, 11, 16]


@pytest.fixture(scope="module")
def measured():
    return geartopo.synth(geartopo.load_scene(EXAMPLES / "warming-truth.yaml"), teeth=TEETH, noise_um=0.5, seed=5)


def test_diagnose_names_the_declared_law_with_its_values(measured):
    d = geartopo.diagnose(geartopo.load_scene(EXAMPLES / "warming.yaml"), measured)
    chosen = d["chosen"]
    assert chosen["effect"] == "workpiece_warming"
    assert chosen["explanation"] == [
        "your effect (custom_effects): deviation_um = -shrink_um_per_mm * (x_mm*nx + y_mm*ny) * (1 - exp(-t_s / tau_s))"]
    for key, truth in (("shrink_um_per_mm", 0.2), ("tau_s", 300.0)):  # warming-truth.yaml's values
        p = chosen["parameters"][key]
        assert abs(p["value"] - truth) <= 2 * p["uncertainty"], (key, p)
    assert d["rms_after_um"] <= 1.5 * 0.5


def test_diagnose_equals_the_cli_and_writes_into_the_users_entry(tmp_path):
    run_cli("synth", EXAMPLES / "warming-truth.yaml", "--out", tmp_path / "m.csv", "--teeth", ",".join(map(str, TEETH)),
            "--noise-um", "0.5", "--seed", "5")
    run_cli("diagnose", EXAMPLES / "warming.yaml", "--measured", tmp_path / "m.csv", "--out", tmp_path / "d")
    d = geartopo.diagnose(geartopo.load_scene(EXAMPLES / "warming.yaml"), str(tmp_path / "m.csv"),
                          yaml_dir=tmp_path / "d")
    yaml = d.pop("scene_with_effect_yaml")
    assert d == json.loads((tmp_path / "d" / "diagnosis.json").read_text())
    assert yaml == (tmp_path / "d" / "scene_with_effect.yaml").read_text()
    # Written back into the user's entry, not appended as a library effect.
    assert "- type: workpiece_warming" not in yaml
    assert "shrink_um_per_mm: {value: 0.2" in yaml
