"""The module as hard to break as the CLI (issue 43): values the CLI refuses are refused here with the argument's
name, by the same code (commands/limits.hpp); a Scene is only made by the module; Ctrl-C stops a long call with
KeyboardInterrupt, with or without a progress callback."""
import copy
import os
import signal
import subprocess
import threading
import time

import pytest

import geartopo
from conftest import MEASURED, ROOT, SCENE, cli_path


@pytest.mark.parametrize("noise", [1e-158, 1e-320, 1e-7, -1.0, float("nan"), float("inf"), 1001.0])
@pytest.mark.parametrize("command", ["compare", "diagnose", "plan"])
def test_a_noise_the_cli_refuses_is_refused_naming_noise_um(scene, command, noise):
    # 1e-158 crashed the interpreter inside the tooth-trend fit; 1e-320 made diagnose's χ² infinite.
    with pytest.raises(ValueError, match=r"noise_um: .* is not a probe noise σ: 0 \(estimated\) or 1e-06 … 1000 µm"):
        getattr(geartopo, command)(scene, str(MEASURED), noise_um=noise)


def test_the_cli_refuses_the_same_noise(tmp_path):
    p = subprocess.run([cli_path(), "compare", str(SCENE), str(MEASURED), "--noise-um", "1e-158",
                        "--out", str(tmp_path / "out")], capture_output=True, text=True, cwd=ROOT)
    assert p.returncode == 2 and "--noise-um" in p.stderr and "1e-06" in p.stderr, p.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("samples", [-1, 10**6 + 1, 10**9])
def test_samples_beyond_the_cli_bound_are_refused_before_any_work(scene, samples):
    # 10**9 ended in MemoryError: std::bad_alloc
    with pytest.raises(ValueError, match=r"samples: .* is not a number of samples: 0 \(nominal only\) … 1000000"):
        geartopo.compensate(scene, samples=samples)


@pytest.mark.parametrize("call", [
    lambda s: geartopo.compare(s, str(MEASURED) + "\0.bak"),
    lambda s: geartopo.diagnose(s, str(MEASURED) + "\0.bak"),
    lambda s: geartopo.machine_values(s, str(MEASURED) + "\0.bak"),
])
def test_a_path_with_a_nul_is_refused_not_cut(scene, call):
    # "m.csv\0.bak" quietly read m.csv
    with pytest.raises(ValueError, match="NUL character"):
        call(scene)


def test_progress_that_cannot_be_called_is_a_type_error_naming_it(scene):
    with pytest.raises(TypeError, match=r"progress: 5 is not callable"):
        geartopo.simulate(scene, teeth=[1], progress=5)


def test_a_scene_is_made_only_by_the_module(scene):
    # Scene.__new__(Scene) made an empty object whose properties read freed memory (a crash)
    with pytest.raises(TypeError, match="load_scene"):
        geartopo.Scene.__new__(geartopo.Scene)
    with pytest.raises(TypeError):
        copy.copy(scene)
    assert scene.teeth == 35  # the module's own objects are made as before


def interrupt_after(seconds):
    """Sends this process SIGINT (Ctrl-C) after `seconds`, from another thread; returns the time it was sent."""
    sent = {}

    def send():
        time.sleep(seconds)
        sent["at"] = time.monotonic()
        os.kill(os.getpid(), signal.SIGINT)

    threading.Thread(target=send, daemon=True).start()
    return sent


@pytest.mark.parametrize("with_callback", [False, True])
def test_ctrl_c_stops_a_long_compensate(scene, with_callback):
    # 10**5 samples run for many minutes; before, Ctrl-C was seen only with a callback, or at the end.
    sent = interrupt_after(2.0)
    progress = (lambda done, total: None) if with_callback else None
    with pytest.raises(KeyboardInterrupt):
        geartopo.compensate(scene, samples=10**5, progress=progress)
    # Each Monte Carlo sample reports; a few samples' time at most, far below the call's own minutes.
    assert time.monotonic() - sent["at"] < 30.0


@pytest.fixture(scope="module")
def fine_scene():
    """The default scene on a 1000 × 1000 grid per flank: a flank takes minutes, a progress report is a flank apart."""
    text = SCENE.read_text().replace("  rows: 7\n  cols: 9\n", "  rows: 1000\n  cols: 1000\n")
    assert "rows: 1000" in text
    return geartopo.scene_from_yaml(text, source=str(SCENE))


# Each stops from the work's inner loops (grinding::SimulationOptions::keep_going: before every grid row), not at the
# next progress report (a flank of this grid) or when the call returns (minutes).
@pytest.mark.parametrize("call", [
    pytest.param(lambda s: geartopo.synth(s, teeth=[1], noise_um=0.0), id="synth"),
    pytest.param(lambda s: geartopo.simulate(s, teeth=[1]), id="simulate"),
    pytest.param(lambda s: geartopo.compensate(s, samples=0), id="compensate-without-samples"),
])
def test_ctrl_c_stops_a_long_call_within_a_second(fine_scene, call):
    sent = interrupt_after(1.0)
    with pytest.raises(KeyboardInterrupt):
        call(fine_scene)
    stopped = time.monotonic() - sent["at"]
    # a grid row of 1000 points takes ~0.05 s on one core; 1 s leaves room for a machine shared with other work
    assert stopped < 1.0, f"stopped {stopped:.2f} s after Ctrl-C"


def test_after_an_interrupt_the_next_call_runs(scene):
    sent = interrupt_after(1.0)
    with pytest.raises(KeyboardInterrupt):
        geartopo.compensate(scene, samples=10**5)
    assert "at" in sent
    r = geartopo.compare(scene, str(MEASURED))
    assert r["overall"]["rms_um"] > 0


@pytest.mark.parametrize("call, error, message", [
    (lambda s: geartopo.compare(s, None), TypeError, r"measured: None is not a measurement: a path"),
    (lambda s: geartopo.compare(s, 5), TypeError, r"measured: 5 is not a measurement"),
    (lambda s: geartopo.machine_values(s, 5), TypeError, r"export: 5 is not a path"),
    (lambda s: geartopo.machine_values(s, str(MEASURED), values=b"x.mew"), TypeError, r"values: b'x.mew' is not a path"),
    (lambda s: geartopo.compare(s, ""), ValueError, r"measured: an empty path names no file"),
])
def test_what_is_not_a_path_is_refused_naming_the_argument(scene, call, error, message):
    with pytest.raises(error, match=message):
        call(scene)


def test_a_path_like_measurement_is_read_as_its_text(scene):
    assert geartopo.compare(scene, MEASURED)["overall"] == geartopo.compare(scene, str(MEASURED))["overall"]


@pytest.mark.parametrize("call, error, message", [
    (lambda s: geartopo.simulate(s, dense="10x10"), TypeError, r"dense: '10x10' is not \(rows, cols\)"),
    (lambda s: geartopo.simulate(s, dense=(1, 2, 3)), TypeError, r"dense: \(1, 2, 3\) is not \(rows, cols\)"),
    (lambda s: geartopo.simulate(s, dense=(2**31, 2)), ValueError, r"dense: \(2147483648, 2\) is not \(rows, cols\) "
                                                                    r"with 2 ≤ each ≤ 1000"),
    (lambda s: geartopo.simulate(s, dense=(2.5, 3)), TypeError, r"dense: \(2.5, 3\) is not \(rows, cols\) of whole"),
    (lambda s: geartopo.simulate(s, teeth=3), TypeError, r"teeth: 3 is not \"all\" or a list"),
    (lambda s: geartopo.simulate(s, teeth={1: 18}), TypeError, r"teeth: \{1: 18\} is not \"all\" or a list"),
    (lambda s: geartopo.diagnose(s, str(MEASURED), yaml_dir=5), TypeError, r"yaml_dir: 5 is not a path"),
    (lambda s: geartopo.evaluate(s, topo=5), TypeError, r"topo: 5 is not a path"),
    (lambda s: geartopo.evaluate(s, topo={**geartopo.simulate(s, teeth=[1]), "traces": 5}), ValueError,
     r"traces: 5 is not a dict of arrays"),
])
def test_arguments_of_the_wrong_shape_are_refused_naming_them(scene, call, error, message):
    # each was a bare "Unable to cast Python instance to C++ type", or read as something else
    with pytest.raises(error, match=message):
        call(scene)


def test_numpy_integers_are_whole_numbers(scene):
    import numpy as np
    t = geartopo.simulate(scene, teeth=np.array([2]), dense=(np.int64(6), 11))
    assert set(t["tooth"]) == {2} and len(t["dense"]["tooth"]) == 2 * 6 * 11


@pytest.mark.parametrize("bad", ["complex", "string"])
def test_measured_arrays_of_complex_or_strings_are_refused(scene, truth, bad):
    import numpy as np
    m = geartopo.synth(truth, teeth=[1], noise_um=0.0)
    m["deviation_um"] = (m["deviation_um"] + 1j) if bad == "complex" else m["deviation_um"].astype(str)
    with pytest.raises(ValueError, match=r"deviation_um: an array of .* is not an array of real numbers"):
        geartopo.compare(scene, m)


# --- every function × every argument with a wrong type ------------------------------------------------------------
# The functions and their arguments are read from the module itself (its public names and each function's signature,
# the first line of its docstring), so a function or an argument added later is walked without editing this test.

class Wrong:
    """An object no argument accepts."""

    def __repr__(self):
        return "<Wrong>"


def public_functions():
    return sorted(n for n in dir(geartopo) if not n.startswith("_") and callable(getattr(geartopo, n))
                  and not isinstance(getattr(geartopo, n), type))


def signature(name):
    """[(argument, annotation, has_default)] of geartopo.<name>, from its pybind11 signature line."""
    import re
    first = getattr(geartopo, name).__doc__.split("\n")[0]
    m = re.fullmatch(rf"{name}\((.*)\) -> .*", first)
    assert m, f"{name}: no signature line in its docstring: {first!r}"
    out, depth, part = [], 0, ""
    for ch in m.group(1) + ",":  # split at the top level's commas (List[str] = [] holds none, a default might)
        if ch == "," and depth == 0:
            if part.strip():
                arg, rest = part.strip().split(":", 1)
                out.append((arg.strip(), rest.split("=")[0].strip(), "=" in rest))
            part = ""
            continue
        depth += ch in "[({" and 1 or 0
        depth -= ch in "])}" and 1 or 0
        part += ch
    return out


# A value of the right type for each required argument, by name (a new function's required argument must be added
# here: the test says which).
REQUIRED = {
    "scene": lambda s: s, "truth": lambda s: s, "measured": lambda s: str(MEASURED), "export": lambda s: str(MEASURED),
    "path": lambda s: str(SCENE), "text": lambda s: SCENE.read_text(), "file": lambda s: str(SCENE),
    # custom_effect: a law no other argument's refusal gets to register (each case has one wrong argument)
    "name": lambda s: "walker_law", "parameters": lambda s: {"k": {"value": 0.0, "min": -1.0, "max": 1.0, "unit": "um"}},
    "fn": lambda s: (lambda params, state: 0.0 * state["t_s"]),
}
# A second wrong value per annotation: the type a user most likely confuses it with.
CONFUSED = {"float": "1.5", "int": 1.5, "str": 5, "bool": "yes", "List[str]": "effect", "geartopo.Scene": str(SCENE)}


def walked():
    cases = []
    for name in public_functions():
        args = signature(name)
        for arg, annotation, _ in args:
            wrongs = [Wrong()] + ([CONFUSED[annotation]] if annotation in CONFUSED else [])
            cases += [pytest.param(name, arg, w, id=f"{name}-{arg}-{type(w).__name__}") for w in wrongs]
    return cases


def test_every_public_function_is_walked():
    names = public_functions()
    assert {"compare", "compensate", "diagnose", "evaluate", "load_scene", "machine_values", "plan", "scene_from_yaml",
            "series", "simulate", "synth"} <= set(names), names
    assert sum(len(signature(n)) for n in names) >= 53  # 11 functions, 53 arguments today


@pytest.mark.parametrize("name, arg, wrong", walked())
def test_a_wrong_type_is_refused_naming_its_argument(scene, name, arg, wrong):
    kwargs = {}
    for a, _, has_default in signature(name):
        if not has_default and a != arg:
            assert a in REQUIRED, f"{name}({a}): add a value of the right type for '{a}' to REQUIRED"
            kwargs[a] = REQUIRED[a](scene)
    kwargs[arg] = wrong
    with pytest.raises((TypeError, ValueError)) as e:
        getattr(geartopo, name)(**kwargs)
    # no bare "incompatible function arguments": the refusal starts with the argument's name
    assert str(e.value).startswith(f"{arg}: "), f"{name}({arg}={wrong!r}): {e.value}"


# --- a trace the ISO evaluation refuses, named with its file and line ----------------------------------------------
GOOD_EXPORT = ROOT / "tests" / "robustness" / "corpus" / "exports" / "reference" / "good.mka"


@pytest.fixture(scope="module")
def z24_scene_file(tmp_path_factory):
    """The default scene with the corpus export's gear (m_n 2, z 24, β 15°, b 20 mm), its tables found from anywhere."""
    text = SCENE.read_text()
    for old, new in [("normal_module_mm: 14", "normal_module_mm: 2"), ("teeth: 35", "teeth: 24"),
                     ("helix_angle_deg: 30 ", "helix_angle_deg: 15 "), ("face_width_mm: 150", "face_width_mm: 20"),
                     ("tip_diameter_mm: 601.4753", "tip_diameter_mm: 54"),
                     ("root_diameter_mm: 538.4753", "root_diameter_mm: 44"), ("profile_shift: 0.274", "profile_shift: 0"),
                     ("machine/", f"{ROOT}/scenes/machine/"), ("measured: demo/", f"measured: {ROOT}/scenes/demo/")]:
        assert old in text, old
        text = text.replace(old, new)
    path = tmp_path_factory.mktemp("z24") / "z24.yaml"
    path.write_text(text)
    return path


def test_a_trace_the_evaluation_refuses_is_named_with_its_file_and_line(z24_scene_file, tmp_path):
    # The corpus export's head, then tooth 1's left profile (line 14) and helix: the profile starts above the
    # evaluation range. Was a bare "tooth 1 left flank, profile: trace refused: …" naming no file, from the CLI and the
    # module alike.
    export = tmp_path / "short.mka"
    export.write_text(GOOD_EXPORT.read_text(encoding="utf-8").split("Profil:")[0] +
                      "Profil:  Zahn-Nr.: 1 links / 5 Werte / z= 10.0\n  .000  1.000  2.000  3.000  4.000\n"
                      "Flankenlinie: Zahn-Nr.: 1 links / 4 Werte / d= 50.0\n  -1.000  -2.000  -3.000  -4.000\n",
                      encoding="utf-8")
    where = r"short\.mka:14: tooth 1 left profile: tooth 1 left flank, profile: trace refused: the trace starts at"
    s = geartopo.load_scene(z24_scene_file)
    with pytest.raises(geartopo.InputError, match=where):
        geartopo.evaluate(s, topo=export)
    with pytest.raises(geartopo.InputError, match=where):
        geartopo.machine_values(s, export)
    p = subprocess.run([cli_path(), "evaluate", str(z24_scene_file), "--traces", str(export), "--out",
                        str(tmp_path / "e")], capture_output=True, text=True, cwd=ROOT)
    assert p.returncode == 1 and "short.mka:14: tooth 1 left profile: " in p.stderr, p.stderr
    assert not (tmp_path / "e").exists()


def test_scene_with_effect_refuses_what_is_not_a_custom_effect(scene):
    for wrong in ("workpiece_warming", {"name": "x"}, None, Wrong()):
        with pytest.raises(TypeError, match="^effect: .* is not a geartopo.CustomEffect"):
            scene.with_effect(wrong)


@pytest.mark.parametrize("key", ["dense_rows", "dense_cols"])
def test_a_scene_dense_grid_has_the_bound_of_dense(key):
    # The scene took up to 10 000 while dense= and --dense stop at 1000: one bound (core/limits.hpp) for all three.
    text = SCENE.read_text().replace("  rows: 7\n", "  rows: 7\n  dense_rows: 1000\n  dense_cols: 1000\n")
    assert geartopo.scene_from_yaml(text, source=str(SCENE)).teeth == 35
    with pytest.raises(geartopo.InputError, match=rf"measurement\.{key}: 1001 is outside \[2, 1000\]"):
        geartopo.scene_from_yaml(text.replace(f"{key}: 1000", f"{key}: 1001"), source=str(SCENE))
