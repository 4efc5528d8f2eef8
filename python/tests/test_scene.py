"""Issue 44's traps of a Scene in Python: its gear is read-only (an assignment to a copy was silently lost), a scene is
changed by its YAML text, a relative load gives a `measured` path usable from the working folder, and a scene read
from text without `source=` names where it looked for its tables."""
import os
import shutil
from pathlib import Path

import pytest

import geartopo
from conftest import ROOT, SCENE


def test_the_gear_is_read_only(scene):
    with pytest.raises(TypeError):
        scene.gear["b_mm"] = 100
    assert scene.gear["b_mm"] == 150  # the default scene's face width, as its file says


def test_a_scene_is_changed_by_its_yaml_text(scene):
    text = scene.yaml.replace("face_width_mm: 150", "face_width_mm: 120")
    assert text != scene.yaml
    narrower = geartopo.scene_from_yaml(text, source=scene.source)  # relative paths still start at the scene's folder
    assert narrower.gear["b_mm"] == 120


def test_measured_of_a_scene_loaded_by_a_relative_path_is_a_path_from_here(monkeypatch):
    monkeypatch.chdir(ROOT)
    scene = geartopo.load_scene(os.path.relpath(SCENE, ROOT))
    assert Path(scene.measured).is_file(), scene.measured
    assert Path(scene.measured).resolve() == (ROOT / "scenes" / "demo" / "measured.csv").resolve()


def test_a_scene_without_its_source_names_where_it_looked_for_a_table(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(geartopo.InputError) as e:
        geartopo.scene_from_yaml(SCENE.read_text())
    message = str(e.value)
    assert e.value.field == "machine.tables"
    assert str(tmp_path / "machine" / "x_axis.csv") in message
    assert "relative to the scene file; this scene has no file name (read from text), so relative to the working folder" in message


def test_a_copied_scene_names_the_scene_line_and_the_resolved_table_path(tmp_path):
    copy = tmp_path / "copy.yaml"
    shutil.copy(SCENE, copy)
    with pytest.raises(geartopo.InputError) as e:
        geartopo.load_scene(copy)
    assert e.value.file == str(copy) and e.value.line > 0
    assert f"{tmp_path / 'machine' / 'x_axis.csv'} does not exist (a table's path is relative to the scene file, in {tmp_path})" in str(e.value)
