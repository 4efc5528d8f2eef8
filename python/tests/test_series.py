"""series(): a production series as `geartopo series` writes it in series.json, exactly; a bad entry refused with its
file and line."""
import json

import pytest

import geartopo
from conftest import SCENE, run_cli


@pytest.fixture(scope="module")
def series_file(tmp_path_factory):
    d = tmp_path_factory.mktemp("series")
    lines = [f"scene: {SCENE}", "gears:"]
    for k in range(4):
        run_cli("synth", SCENE, "--out", d / f"g{k}.csv", "--format", "traces", "--seed", 10 + k, "--noise-um", "0.3")
        lines += [f"  - measurement: g{k}.csv", f"    start_s: {900 * k}"]
    (d / "series.yaml").write_text("\n".join(lines) + "\n")
    return d / "series.yaml"


def test_series_equals_series_json(series_file, tmp_path):
    run_cli("series", series_file, "--out", tmp_path / "out")
    cli = json.loads((tmp_path / "out" / "series.json").read_text())
    py = geartopo.series(str(series_file))
    assert py == cli
    assert [q["chosen"]["model"] for q in py["quantities"]][:3] == ["noise only"] * 3


def test_series_refuses_a_gear_out_of_order(series_file, tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text(series_file.read_text().replace("start_s: 900", "start_s: 9000"))
    with pytest.raises(geartopo.InputError, match=r"bad\.yaml:8:\d+: gears\[2\]\.start_s"):
        geartopo.series(str(bad))


def test_diagnose_gears_gives_each_gear_the_verdict_of_diagnose(series_file):
    # The series file's gears are synthetic measurements of the scene itself (probe noise only): each gear's diagnosis,
    # run as `diagnose` runs it, names nothing and says so; the key in the file and the argument ask for the same.
    py = geartopo.series(str(series_file), diagnose_gears=True)
    for g in py["gears"]:
        assert g["diagnosis"]["chosen"] is None, g["diagnosis"]["verdict"]
        assert g["diagnosis"]["verdict"]
    single = geartopo.diagnose(geartopo.load_scene(SCENE), str(series_file.parent / "g0.csv"))
    assert py["gears"][0]["diagnosis"]["verdict"] == single["verdict"]
    with_key = series_file.parent / "with_key.yaml"
    with_key.write_text("diagnose_gears: true\n" + series_file.read_text())
    assert [g["diagnosis"] for g in geartopo.series(str(with_key))["gears"]] == [g["diagnosis"] for g in py["gears"]]
    assert "diagnosis" not in geartopo.series(str(series_file))["gears"][0]
