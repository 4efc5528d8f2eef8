"""Errors: the CLI's located messages as Python exceptions (geartopo.InputError is a ValueError), bad arguments as
ValueError naming the argument."""
import subprocess

import numpy as np
import pytest

import geartopo
from conftest import MEASURED, SCENE, cli_path, run_cli


def broken_scene_text():
    """The default scene with gear.teeth spoiled: the error is located at its line and column."""
    return SCENE.read_text().replace("teeth: 35", "teeth: -3", 1)


def test_a_broken_scene_file_gives_the_cli_message(tmp_path):
    broken = tmp_path / "broken.yaml"
    broken.write_text(broken_scene_text())
    proc = run_cli("gear", broken, expect=1)
    cli_message = proc.stderr.strip().removeprefix("geartopo: error: ")
    with pytest.raises(geartopo.InputError) as e:
        geartopo.load_scene(broken)
    assert str(e.value) == cli_message
    assert isinstance(e.value, ValueError)
    assert e.value.file == str(broken) and e.value.field == "gear.teeth" and e.value.line > 0 and e.value.column > 0
    assert str(e.value).startswith(f"{broken}:{e.value.line}:{e.value.column}: gear.teeth: ")


def test_a_broken_yaml_text_is_located_in_its_source():
    with pytest.raises(ValueError, match=r"^mine\.yaml:\d+:\d+: gear\.teeth: "):
        geartopo.scene_from_yaml(broken_scene_text(), source="mine.yaml")


def test_a_missing_file_is_an_input_error(tmp_path):
    with pytest.raises(geartopo.InputError, match="does not exist"):
        geartopo.load_scene(tmp_path / "nothing.yaml")


def test_a_measurement_file_error_is_located(scene, tmp_path):
    bad = tmp_path / "bad.csv"
    lines = MEASURED.read_text().splitlines()
    lines[3] = lines[3].replace("left", "middle")
    bad.write_text("\n".join(lines) + "\n")
    proc = run_cli("compare", SCENE, "--measured", bad, "--out", tmp_path / "c", expect=1)
    with pytest.raises(geartopo.InputError) as e:
        geartopo.compare(scene, str(bad))
    assert str(e.value) == proc.stderr.strip().removeprefix("geartopo: error: ")
    assert e.value.line == 4 and e.value.field == "flank"


def test_measured_arrays_are_checked_element_by_element(scene, truth):
    m = geartopo.synth(truth)
    m["flank"] = m["flank"].astype("<U6")
    m["flank"][2] = "middle"
    with pytest.raises(geartopo.InputError, match=r"^measured arrays:3: flank: 'middle' is not left or right$"):
        geartopo.compare(scene, m)
    m = geartopo.synth(truth)
    m["deviation_um"][4] = np.nan
    with pytest.raises(ValueError, match=r"^measured arrays:5: deviation_um: nan is not finite$"):
        geartopo.compare(scene, m)
    m = geartopo.synth(truth)
    m["diameter_mm"][0] = 100.0
    with pytest.raises(ValueError, match=r"^measured arrays:1: diameter_mm: 100\.0000 mm is off the flank"):
        geartopo.compare(scene, m)
    m = geartopo.synth(truth)
    m["z_mm"] = m["z_mm"][:-1]
    with pytest.raises(ValueError, match=r"^measured arrays: z_mm: 251 values, the other columns have 252$"):
        geartopo.compare(scene, m)
    del m["z_mm"]
    with pytest.raises(ValueError, match=r"^measured arrays: z_mm: no column 'z_mm'"):
        geartopo.compare(scene, m)


def test_a_tooth_number_is_a_whole_number_never_truncated(scene, truth):
    m = geartopo.synth(truth)
    m["tooth"] = m["tooth"].astype(float)
    m["tooth"][6] = 1.5
    with pytest.raises(geartopo.InputError, match=r"^measured arrays:7: tooth: 1\.5 is not a whole number"):
        geartopo.compare(scene, m)
    m["tooth"][6] = 2.0**32 + 1  # numpy's cast to int would wrap it round to tooth 1
    with pytest.raises(geartopo.InputError, match=r"^measured arrays:7: tooth: 4294967297 is not a whole number"):
        geartopo.compare(scene, m)
    m["tooth"][6] = m["tooth"][5]  # a whole number given as a float is read
    geartopo.compare(scene, m)


@pytest.mark.parametrize("call, message", [
    (lambda s: geartopo.simulate(s, method="quadratic"), "method: 'quadratic' is not exact or linear"),
    (lambda s: geartopo.simulate(s, teeth=[0]), "teeth: 0 is not a tooth number of 1..35"),
    (lambda s: geartopo.simulate(s, teeth=[3, 3]), "teeth: tooth 3 is listed twice"),
    (lambda s: geartopo.simulate(s, teeth="some"), "teeth: 'some' is not \"all\" or a list"),
    (lambda s: geartopo.simulate(s, teeth=[1.5]), "teeth: 1.5 is not a tooth number \\(a whole number of 1..35\\)"),
    (lambda s: geartopo.simulate(s, teeth=[True]), "teeth: True is not a tooth number"),
    (lambda s: geartopo.simulate(s, teeth=[1e300]), "teeth: 1e\\+300 is not a tooth number of 1..35"),
    (lambda s: geartopo.simulate(s, dense=(1, 5)), "dense: \\(1, 5\\) is not"),
    (lambda s: geartopo.evaluate(s, iso_direction="sideways"), "iso_direction: 'sideways' is not transverse or normal"),
    (lambda s: geartopo.compensate(s, method="magic"), "method: 'magic' is not paper, flank or cycle"),
    (lambda s: geartopo.compare(s, str(MEASURED), noise_um=-1), "noise_um: -1"),
])
def test_bad_arguments_are_value_errors_naming_the_argument(scene, call, message):
    with pytest.raises(ValueError, match=message):
        call(scene)
