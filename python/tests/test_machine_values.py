"""machine_values(): the measuring machine's own evaluation beside geartopo's, as `geartopo evaluate --traces EXPORT
--machine-values VALUES` writes it into iso1328.json ("machine_pitch_table", "machine_flank_values"), exactly.

The export and the value file are written here from the documented structure (docs/measurement-formats.md, "Curve
file", "Pitch tables", "Value file"), for the default scene (m_n 14, z 35, d_Ff 547.62, d_a 601.4753, b 150 mm):
every tooth measured with one profile trace at mid face width and one helix trace at d = 585 mm, so geartopo
evaluates pitch and the export's pitch table is compared row by row."""
import json
import math

import pytest

import geartopo
from conftest import SCENE, run_cli

Z = 35
KEYS = ("machine_pitch_table", "machine_flank_values")


def export_text():
    """A Klingelnberg curve file: per tooth and flank a profile trace (z = 75 mm) over d 547.616 … 601.475 mm (d_Ff … d_a) and a helix
    trace (d = 585 mm) over z 0 … 150 mm, 40 values each (µm: slope, crowning and a per-tooth offset), and the pitch
    tables of both sides."""
    lines = ["HEADER KS.MK.FILE", "TYPE       STI   ! written by test_machine_values.py",
             "  21 :Normalmodul mn [mm]...............: 14.0000",
             "  22 :Zähnezahl z.......................: 35",
             "  41 :Start Messbereich.....da [mm].....: 547.6160 547.6160",
             "  44 :Ende der Messstrecke..de [mm].....: 601.4750 601.4750",
             "  61 :Messanfang............ba [mm].....: 0.0000 0.0000",
             "  64 :Messende..............be [mm].....: 150.0000 150.0000"]
    n = 40

    def values(offset, slope, crown):
        u = [-1 + 2 * i / (n - 1) for i in range(n)]
        v = [f"{offset + slope * x + crown * (x * x - 1 / 3):.4f}" for x in u]
        return [" ".join(v[k:k + 10]) for k in range(0, n, 10)]

    for tooth in range(1, Z + 1):
        for k, name in enumerate(("links", "rechts")):
            offset = (0.9 if k == 0 else -0.7) * math.sin(2 * math.pi * tooth / Z) + 0.15 * ((tooth * 7) % 5 - 2)
            lines.append(f"Profil:  Zahn-Nr.: {tooth} {name} / {n} Werte / z= 75.0000")
            lines += values(offset, 2.5 - 0.1 * (tooth % 4) - k, 1.1 + 0.2 * k)
            lines.append(f"Flankenlinie: Zahn-Nr.: {tooth} {name} / {n} Werte / d= 585.0000")
            lines += values(offset, -1.8 + 0.05 * (tooth % 3) + 2.5 * k, 0.9)
    for k, title in enumerate(("linke Zahnflanke", "rechte Zahnflanke")):
        lines += [title, "Zahn-Nr.   fp     Fp     Fr"]
        for tooth in range(1, Z + 1):
            fp = (0.8 - 0.3 * k) * math.cos(2 * math.pi * tooth / Z) + 0.1 * (tooth % 3)
            Fp = 2.0 * math.sin(2 * math.pi * (tooth - 1) / Z) * (1 - 0.4 * k)
            lines.append(f"  {tooth}  {fp:.4f}  {Fp:.4f}  1.2000")
    return "\n".join(lines) + "\n"


def value_file_text():
    """A Klingelnberg value file: f_Hα, f_fα, F_α, f_Hβ, f_fβ, F_β of teeth 1 (slot 1) and 18 (slot 2), both flanks
    (code G MM S T, label "<name> <flank> <tooth>"), one placeholder, one "-0.0000", a size line geartopo does not read, a filter and
    the sign setting 178."""
    lines = ["\ufeffHEADER KS.MW.FILE", "TYPE       STI   ! written by test_machine_values.py", "FILTER LEAD:    F:S 2",
             "  22 :Zähnezahl z.......................: 35", " 178 :Vorzeichen Flankenlinie...........: LVORZ: 1: DIN"]
    kinds = ((2, "01", "fHa"), (2, "07", "ffa"), (2, "04", "Fa"), (1, "01", "fHb"), (1, "07", "ffb"), (1, "04", "Fb"))
    for slot, tooth in ((1, 1), (2, 18)):
        for s, flank in ((1, "links"), (2, "rechts")):
            for q, (g, mm, name) in enumerate(kinds):
                value = 0.4 * q - 1.1 + 0.3 * slot + 0.2 * s
                if (tooth, flank, name) == (18, "rechts", "ffb"):
                    value = -9999.0  # not measured
                if (tooth, flank, name) == (1, "rechts", "ffa"):
                    value = -0.0  # written "-0.0000", as machines do
                lines.append(f"{g}{mm}{s}{slot} : {name} {flank} {tooth} : {value:.4f}")
    lines.append("30011 : Fuß links 1 : 538.4000")
    return "\r\n".join(lines) + "\r\n"


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("machine_values")
    (d / "gear.mka").write_text(export_text(), encoding="utf-8")
    (d / "values.mew").write_text(value_file_text(), encoding="utf-8")
    return d / "gear.mka", d / "values.mew"


def cli_json(tmp_path, *args):
    """iso1328.json of `geartopo evaluate`, and what it printed."""
    proc = run_cli("evaluate", SCENE, "--out", tmp_path, *args)
    return json.loads((tmp_path / "iso1328.json").read_text()), proc.stdout


@pytest.mark.parametrize("direction", ["transverse", "normal"])
def test_machine_values_equal_iso1328_json(scene, files, tmp_path, direction):
    mka, mew = files
    cli, printed = cli_json(tmp_path / "e", "--traces", mka, "--machine-values", mew, "--iso-direction", direction)
    with pytest.warns(UserWarning, match="result lines not read"):
        py = geartopo.machine_values(scene, str(mka), str(mew), iso_direction=direction)
    assert py == {k: cli[k] for k in KEYS}
    # Both parts compared something: every tooth's pitch rows, teeth 1 and 18's six values less the placeholder.
    assert len(py["machine_pitch_table"]["rows"]) == 2 * Z
    assert len(py["machine_flank_values"]["rows"]) == 23
    assert py["machine_flank_values"]["not_compared"]
    # The value file's -0.0000 (f_fα tooth 1 right) is printed as 0.000 in the console's table, never -0.000.
    assert "-0.000 " not in printed and "    0.000 " in printed


def test_without_a_value_file_only_the_pitch_table(scene, files, tmp_path):
    mka, _ = files
    cli, _ = cli_json(tmp_path / "e", "--traces", mka)
    assert "machine_flank_values" not in cli
    assert geartopo.machine_values(scene, mka) == {"machine_pitch_table": cli["machine_pitch_table"]}


def test_a_file_that_is_not_an_export_is_refused_by_name(scene, files, tmp_path):
    _, mew = files
    traces = tmp_path / "traces.csv"
    run_cli("synth", SCENE, "--out", traces, "--format", "traces")
    cli = run_cli("evaluate", SCENE, "--traces", traces, "--machine-values", mew, "--out", tmp_path / "e", expect=2)
    assert "is not a Klingelnberg export" in cli.stderr
    with pytest.raises(ValueError, match=r"traces\.csv is not a Klingelnberg export"):
        geartopo.machine_values(scene, traces, mew)


def test_a_bad_value_file_is_an_input_error_as_the_cli_says(scene, files, tmp_path):
    mka, mew = files
    bad = tmp_path / "bad.mew"
    bad.write_text(value_file_text().replace("20111 : fHa links 1 :", "20111 : fHb links 1 :"), encoding="utf-8")
    cli = run_cli("evaluate", SCENE, "--traces", mka, "--machine-values", bad, "--out", tmp_path / "e", expect=1)
    with pytest.raises(geartopo.InputError) as e:
        geartopo.machine_values(scene, mka, bad)
    assert e.value.file == str(bad)
    assert "code and label disagree" in e.value.message
    assert str(e.value) in cli.stderr


def test_an_export_with_cr_only_line_endings_reads_as_with_lf(scene, files, tmp_path):
    # An export saved with CR-only line endings was one line to the reader: "1:642: z=: '10.0' is not a number".
    mka, mew = files
    cr = tmp_path / "cr.mka"
    cr.write_bytes(mka.read_bytes().replace(b"\r\n", b"\n").replace(b"\n", b"\r"))
    assert b"\n" not in cr.read_bytes()
    assert geartopo.machine_values(scene, cr, mew) == geartopo.machine_values(scene, mka, mew)
