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
