"""Your own physics as a Python function (geartopo.custom_effect, issue 40 item 2), checked against physics written
HERE, not with the function under test, on the default gear (right hand) and on the same gear left-handed.

The physics: a workpiece that warms while it is ground and shrinks when it cools. The material ground while the gear
was warm by k·ΔT had expanded radially by k·ΔT·r, so after cooling each ground point lies k·ΔT·(x, y, 0) further in:
projected on the flank's outward normal, −k·ΔT·(x, y, 0)·n. For an involute helicoid (x, y, 0)·n = ξ·cos β_b — the
transverse normal is tangent to the base circle, so the position's component along it is the roll length ξ = √(r² −
r_b²) — which is what the truth below uses (from the point's diameter and the gear's base diameter and base helix
angle), while the law under test gets x, y, nx, ny from the library. ΔT is written per stroke: the n-th stroke of the
job (sequential indexing from space 1: space s is stroke s − 1; space s holds the right flank of tooth s and the left
flank of tooth s + 1) grinds a gear warmed to 1 − exp(−n/N) of its steady state."""
import math

import numpy as np
import pytest

import geartopo
from conftest import SCENE

TEETH = [1, 12, 18, 30]


def scene_text(left_hand):
    t = SCENE.read_text()
    if left_hand:
        t = t.replace("helix_angle_deg: 30 ", "helix_angle_deg: -30 ", 1).replace("hand: right", "hand: left", 1)
    return t


@pytest.fixture(scope="module", params=[False, True], ids=["right-hand", "left-hand"])
def plain(request):
    return geartopo.scene_from_yaml(scene_text(request.param), source=str(SCENE))


def stroke_warming(params, state):
    """The law under test, vectorised: one call per batch of points."""
    warmed = 1.0 - np.exp(-state["stroke"] / params["strokes_to_warm"])
    return -params["shrink_um_per_mm"] * (state["x_mm"] * state["nx"] + state["y_mm"] * state["ny"]) * warmed


def time_warming(params, state):
    return -params["shrink_um_per_mm"] * (state["x_mm"] * state["nx"] + state["y_mm"] * state["ny"]) * (
        1.0 - np.exp(-state["t_s"] / params["tau_s"]))


TIME_LAW = "-shrink_um_per_mm * (x_mm*nx + y_mm*ny) * (1 - exp(-t_s / tau_s))"


def warming_parameters(k, n):
    return {"shrink_um_per_mm": {"value": k, "min": -0.1, "max": 0.1, "unit": "um_per_mm"},
            "strokes_to_warm": {"value": n, "min": 1, "max": 1000, "unit": "strokes"}}


def time_parameters(k, tau):
    return {"shrink_um_per_mm": {"value": k, "min": -0.1, "max": 0.1, "unit": "um_per_mm"},
            "tau_s": {"value": tau, "min": 30, "max": 20000, "unit": "s"}}


def physics_um(scene, m, k, n_strokes):
    """−k·ΔT(stroke)·ξ·cos β_b at each measured point (the module docstring's physics)."""
    gear = scene.gear
    rb = gear["db_mm"] / 2.0
    xi = np.sqrt((m["diameter_mm"] / 2.0) ** 2 - rb ** 2)
    teeth = scene.teeth
    space = np.where(m["flank"] == "right", m["tooth"], (m["tooth"] - 2) % teeth + 1)
    warmed = 1.0 - np.exp(-(space - 1) / n_strokes)
    return -k * warmed * xi * math.cos(math.radians(abs(gear["beta_b_deg"])))


def hand(scene):
    return "lh" if scene.gear["beta_deg"] < 0 else "rh"


def test_synth_with_the_python_law_is_the_physics_to_ten_nanometres(plain):
    k, n = 0.04, 12.0
    effect = geartopo.custom_effect(f"stroke_warming_{hand(plain)}", warming_parameters(k, n), stroke_warming)
    truth = plain.with_effect(effect)
    with_law = geartopo.synth(truth, teeth=TEETH, noise_um=0.0)
    without = geartopo.synth(plain, teeth=TEETH, noise_um=0.0)
    for key in ("tooth", "flank", "diameter_mm", "z_mm"):
        assert np.array_equal(with_law[key], without[key])
    physics = physics_um(plain, without, k, n)
    worst = np.max(np.abs(with_law["deviation_um"] - without["deviation_um"] - physics))
    print(f"{hand(plain)}: synth − physics at most {worst:.2e} µm of a physics up to {np.max(np.abs(physics)):.2f} µm")
    assert np.max(np.abs(physics)) > 1.0  # the effect is there to be seen
    assert worst <= 0.01


def test_diagnose_told_the_python_law_names_it_within_two_sigma(plain):
    truth_k, truth_tau = 0.04, 200.0
    name = f"time_warming_{hand(plain)}"
    truth = plain.with_effect(geartopo.custom_effect(name, time_parameters(truth_k, truth_tau), time_warming))
    measured = geartopo.synth(truth, teeth=TEETH, noise_um=0.5, seed=3)
    told = plain.with_effect(geartopo.custom_effect(name, time_parameters(0.0, 300.0), time_warming))
    d = geartopo.diagnose(told, measured)
    chosen = d["chosen"]
    assert chosen["effect"] == name
    assert chosen["explanation"] == [
        f"your effect (Python function {__name__}.time_warming): deviation_um = {__name__}.time_warming(params, state)"]
    for key, value in (("shrink_um_per_mm", truth_k), ("tau_s", truth_tau)):
        p = chosen["parameters"][key]
        assert abs(p["value"] - value) <= 2 * p["uncertainty"], (key, p)
    assert d["rms_after_um"] <= 1.5 * 0.5
    # Written back into the user's own entry, the function named.
    yaml = d["scene_with_effect_yaml"]
    assert f"python: {__name__}.time_warming" in yaml and f"- type: {name}" not in yaml


def test_the_same_law_as_expression_and_as_python_function_gives_the_same_results(plain):
    """The fit's model evaluates the function at the measured points themselves (one call per 1024 points): the same
    values as the expression's to rounding (the fitted values agree to 1e-9). simulate evaluates it on each stroke's
    grid (one call per stroke, in Z and the roll length ξ) and interpolates: this law is linear in ξ and smooth in Z,
    so the grid leaves ~1e-10 µm (printed)."""
    name = f"same_law_{hand(plain)}"
    as_python = plain.with_effect(geartopo.custom_effect(name, time_parameters(0.04, 200.0), time_warming))
    as_expression = geartopo.scene_from_yaml(
        plain.yaml + f"""
custom_effects:
  - name: {name}_expr
    parameters:
      shrink_um_per_mm: {{value: 0.04, min: -0.1, max: 0.1, unit: um_per_mm}}
      tau_s: {{value: 200, min: 30, max: 20000, unit: s}}
    deviation_um: "{TIME_LAW}"
""", source=str(SCENE))
    measured = geartopo.synth(as_expression, teeth=TEETH, noise_um=0.5, seed=4)
    fits = []
    for scene in (as_python, as_expression):
        d = geartopo.diagnose(scene, measured)
        fits.append((d["chosen"]["parameters"], d["rms_after_um"]))
    for key in ("shrink_um_per_mm", "tau_s"):
        a, b = fits[0][0][key], fits[1][0][key]
        assert a["value"] == pytest.approx(b["value"], rel=1e-9, abs=1e-12), key
        assert a["uncertainty"] == pytest.approx(b["uncertainty"], rel=1e-6), key
    # rms_after comes from the exact simulation of the fitted effect: through the stroke grid.
    assert fits[0][1] == pytest.approx(fits[1][1], abs=1e-9)
    for method, tolerance_um in (("linear", 1e-9), ("exact", 1e-9)):
        a = geartopo.simulate(as_python, teeth=TEETH, method=method)["deviation_um"]
        b = geartopo.simulate(as_expression, teeth=TEETH, method=method)["deviation_um"]
        print(f"{hand(plain)} {method}: Python law − expression at most {np.max(np.abs(a - b)):.2e} µm")
        assert np.max(np.abs(a - b)) <= tolerance_um


def test_one_call_per_batch_and_the_same_results_at_any_thread_count(plain):
    sizes = []

    def counted(params, state):
        sizes.append(len(state["t_s"]))
        return time_warming(params, state)

    effect = geartopo.custom_effect(f"counted_{hand(plain)}", time_parameters(0.04, 200.0), counted)
    scene = plain.with_effect(effect)
    # The scene's check: the grid's points on every tooth and flank (35 × 2 × 7 × 9) in one call.
    assert sizes == [35 * 2 * 7 * 9], sizes
    sizes.clear()
    one = geartopo.simulate(scene, teeth=[1, 18], threads=1)
    # Teeth 1 and 18 lie in spaces 35, 1, 17 and 18: one call per stroke (its grid), not per point.
    assert len(sizes) == 4 and min(sizes) > 1000, sizes
    # A scene of its own, so that its strokes' grids are made again, by two threads.
    two = geartopo.simulate(plain.with_effect(effect), teeth=[1, 18], threads=2)
    assert np.array_equal(one["deviation_um"], two["deviation_um"])


class Boom(Exception):
    pass


def test_an_exception_inside_the_function_is_raised_as_itself(plain):
    armed = [False]

    def law(params, state):
        if armed[0]:
            raise Boom("the user's own error")
        return time_warming(params, state)

    scene = plain.with_effect(geartopo.custom_effect(f"boom_{hand(plain)}", time_parameters(0.04, 200.0), law))
    armed[0] = True
    for threads in (1, 2):
        with pytest.raises(Boom, match="the user's own error"):
            geartopo.simulate(scene, teeth=[1, 18], threads=threads)
    with pytest.raises(Boom):
        plain.with_effect(geartopo.custom_effect(f"boom2_{hand(plain)}", time_parameters(0.04, 200.0), law))


def test_a_wrong_shape_or_a_non_finite_value_is_refused_naming_the_point(plain):
    def scalar(params, state):
        return 1.0

    def short(params, state):
        return np.zeros(len(state["t_s"]) - 1)

    for law, said in ((scalar, "returned a float"), (short, "returned an array of shape")):
        effect = geartopo.custom_effect(f"{law.__name__}_{hand(plain)}", time_parameters(0.04, 200.0), law)
        with pytest.raises(ValueError) as e:
            plain.with_effect(effect)
        message = str(e.value)
        assert f"custom effect '{law.__name__}_{hand(plain)}'" in message and said in message, message
        assert "tooth " in message and " flank, d = " in message and "t_s = " in message, message

    def hot_tip(params, state):
        out = time_warming(params, state)
        out[state["r_mm"] > np.max(state["r_mm"]) - 1e-9] = np.nan
        return out

    with pytest.raises(geartopo.InputError) as e:
        plain.with_effect(geartopo.custom_effect(f"hot_tip_{hand(plain)}", time_parameters(0.04, 200.0), hot_tip))
    message = str(e.value)
    assert f"custom effect 'hot_tip_{hand(plain)}': deviation_um = nan is not finite at tooth " in message, message
    assert "shrink_um_per_mm = 0.04, tau_s = 200, t_s = " in message and "wheel_r_mm = " in message, message


def test_a_law_refused_for_a_clash_or_bad_parameters():
    with pytest.raises(ValueError, match="effect of the library"):
        geartopo.custom_effect("thermal_drift", time_parameters(0.0, 300.0), time_warming)
    with pytest.raises(ValueError, match="min"):
        geartopo.custom_effect("no_bounds", {"k": {"value": 0.0, "max": 1.0, "unit": "um"}}, time_warming)
    geartopo.custom_effect("taken", time_parameters(0.0, 300.0), time_warming)
    with pytest.raises(ValueError, match="another law"):
        geartopo.custom_effect("taken", time_parameters(0.0, 300.0), stroke_warming)
    # The same function under the same name again (a notebook cell run twice, other values) is the same law.
    again = geartopo.custom_effect("taken", time_parameters(0.01, 300.0), time_warming)
    assert again.parameters["shrink_um_per_mm"]["value"] == 0.01


def test_the_tutorials_python_block_prints_what_the_tutorial_shows(monkeypatch, capsys):
    """docs/tutorial.md, "The same law as a Python function": the ```python block run as written (from the
    repository's folder), its output the untagged block after it."""
    from conftest import ROOT
    text = (ROOT / "docs" / "tutorial.md").read_text()
    section = text[text.index("### The same law as a Python function"):]
    code = section.split("```python\n", 1)[1].split("```", 1)[0]
    expected = section.split("```python\n", 1)[1].split("```", 1)[1].split("```\n", 1)[1].split("```", 1)[0]
    monkeypatch.chdir(ROOT)
    exec(compile(code, "docs/tutorial.md", "exec"), {"__name__": "tutorial"})
    assert capsys.readouterr().out == expected


def test_the_scenes_yaml_names_the_function_and_the_cli_refuses_it(tmp_path):
    from conftest import ROOT, run_cli
    effect = geartopo.custom_effect("yaml_warming", time_parameters(0.04, 200.0), time_warming)
    scene = geartopo.load_scene(ROOT / "docs" / "examples" / "warming-plain.yaml").with_effect(effect)
    assert ("shrink_um_per_mm: {value: 0.04, min: -0.1, max: 0.1, unit: um_per_mm}" in scene.yaml
            and f"python: {__name__}.time_warming" in scene.yaml), scene.yaml
    # Read again in this process: the same law.
    again = geartopo.scene_from_yaml(scene.yaml, source=scene.source)
    assert np.array_equal(geartopo.simulate(again, teeth=[1])["deviation_um"],
                          geartopo.simulate(scene, teeth=[1])["deviation_um"])
    (tmp_path / "s.yaml").write_text(scene.yaml)
    proc = run_cli("simulate", tmp_path / "s.yaml", "--out", tmp_path / "o", expect=1)
    assert f"'yaml_warming' is a law given as the Python function {__name__}.time_warming" in proc.stderr, proc.stderr


def test_compensate_and_its_monte_carlo_take_the_python_law_as_the_expression():
    """On the tutorial's small gear (m_n 4, z 20): the corrections, the topologies before and after and the Monte
    Carlo's prediction, the law's value drawn within its uncertainty, as with the same law written as an expression."""
    from conftest import ROOT
    plain = geartopo.load_scene(ROOT / "docs" / "examples" / "warming-plain.yaml")
    p = time_parameters(0.2, 300.0)
    p["shrink_um_per_mm"].update(max=0.5, uncertainty=0.03)
    as_python = plain.with_effect(geartopo.custom_effect("mc_warming", p, time_warming))
    as_expression = geartopo.scene_from_yaml(plain.yaml + f"""
custom_effects:
  - name: mc_warming_expr
    uncertainty: {{shrink_um_per_mm: 0.03}}
    parameters:
      shrink_um_per_mm: {{value: 0.2, min: -0.1, max: 0.5, unit: um_per_mm}}
      tau_s: {{value: 300, min: 30, max: 20000, unit: s}}
    deviation_um: "{TIME_LAW}"
""", source=plain.source)
    a, b = (geartopo.compensate(s, samples=8) for s in (as_python, as_expression))
    for key in ("before", "nominal_after"):
        assert np.max(np.abs(a[key]["deviation_um"] - b[key]["deviation_um"])) <= 1e-8, key
    assert np.max(np.abs(a["corrections"]["dX_um"] - b["corrections"]["dX_um"])) <= 1e-6
    la, lb = a["prediction"]["limit"], b["prediction"]["limit"]
    assert la["limiting_median_after_um"] == pytest.approx(lb["limiting_median_after_um"], abs=1e-6)
    exact = dict(p, shrink_um_per_mm={k: v for k, v in p["shrink_um_per_mm"].items() if k != "uncertainty"})
    without = geartopo.compensate(
        plain.with_effect(geartopo.custom_effect("mc_warming_exact", exact, time_warming)), samples=8)
    assert abs(without["prediction"]["limit"]["limiting_median_after_um"] - la["limiting_median_after_um"]) > 1e-3
