#!/usr/bin/env python3
"""Writes the broken-input corpus replayed by tests/robustness/test_corpus.cpp.

The files are kept in the repository; this script documents how each was made (and remakes them). Every file must be
refused with a clear message: the expected exception, line and message fragment of each are in
<folder>/expected.tsv (one row per file; the test fails for a file without a row or a row without a file).

Run from anywhere:  python3 tests/robustness/corpus/make_corpus.py
"""
import os
import random

HERE = os.path.dirname(os.path.abspath(__file__))

GEAR = """gear:
  normal_module_mm: 14
  teeth: 35
  normal_pressure_angle_deg: 20
  helix_angle_deg: 30
  profile_shift: 0.274
  face_width_mm: 150
"""

def gear(**over):
    """The seed paper's gear with some keys replaced (value None: key removed)."""
    keys = {"normal_module_mm": "14", "teeth": "35", "normal_pressure_angle_deg": "20", "helix_angle_deg": "30",
            "profile_shift": "0.274", "face_width_mm": "150"}
    extra = {}
    for k, v in over.items():
        if k in keys:
            if v is None:
                del keys[k]
            else:
                keys[k] = v
        else:
            extra[k] = v
    keys.update(extra)
    return "gear:\n" + "".join(f"  {k}: {v}\n" for k, v in keys.items())


def write(folder, name, data, expected, note=""):
    path = os.path.join(HERE, folder, name)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    mode = "wb" if isinstance(data, bytes) else "w"
    with open(path, mode, **({} if mode == "wb" else {"newline": ""})) as f:
        f.write(data)
    ROWS.setdefault(folder, []).append((name,) + expected + (note,))


ROWS = {}
rng = random.Random(20261121)
junk = bytes(rng.randrange(256) for _ in range(4096))

# ---------------------------------------------------------------------------------------------------- scenes
# expected: (exception, line (0: none expected, -1: any), message fragment)
S = "scenes"
write(S, "syntax_unclosed_bracket.yaml", GEAR + "measurement:\n  teeth: [1, 2\n", ("InputError", -1, "YAML syntax error"))
write(S, "syntax_bad_indent.yaml", "gear:\n  normal_module_mm: 14\n teeth: 35\n", ("InputError", -1, "YAML syntax error"))
write(S, "syntax_tab_indent.yaml", "gear:\n\tnormal_module_mm: 14\n", ("InputError", -1, "YAML syntax error"))
# yaml-cpp 0.7 lets an unterminated double quote run to the end of the file: refused, but as "gear: missing".
# Found by fuzz_scene (finding 22): yaml-cpp 0.7 hangs for ever when a document's first token is ','.
write(S, "syntax_leading_comma_hang.yaml", ",` ! \n\n  \n", ("InputError", 1, "cannot start with ','"))
write(S, "syntax_leading_comma_second_document.yaml", GEAR + "---\n, x\n", ("InputError", -1, "cannot start with ','"))
# The second fuzzing run: NULs in front of the ',' hid it from the first fix (YAML allows no control characters).
write(S, "syntax_nul_then_comma_hang.yaml", "\0\0\0,gear:\n  teeth: 35\n", ("InputError", 1, "control character U+0000"))
# The third: a tag (or an anchor) in front of the ',' hung it as well (the fuzzer's input: " ! ," then 0xFF bytes).
write(S, "syntax_tag_then_comma_hang.yaml", b" ! ," + b"\xff" * 70 + b"` ! \n\n  \n", ("InputError", 1, "cannot start with ','"))
write(S, "syntax_anchor_then_comma_hang.yaml", "&a ,gear:\n  teeth: 35\n", ("InputError", 1, "cannot start with ','"))
# The fourth and fifth: a ',' after a complete root node (an anchored scalar, a list, a quoted or flow node), or after
# node properties alone on a line, made LoadAll loop for ever, a null document per turn (yaml-cpp#1040; 18 bytes took
# 2 GB within a second): refused where the second document starts. The fuzzers' inputs, a list and an anchor.
write(S, "syntax_comma_after_root_hang.yaml", b"&a\xe5#0t\x8ce anchor(\n,g35\n", ("InputError", 2, "after the document's root node"))
write(S, "syntax_comma_after_list_hang.yaml", "- gear\n,\n", ("InputError", 2, "after the document's root node"))
write(S, "syntax_tag_line_then_comma_oom.yaml", b"...  \n\n!\n\n,\x8eeix\xff\x9ci", ("InputError", 3, "after the document's root node"))
write(S, "syntax_anchor_line_then_comma_oom.yaml", "&a # the anchor\n\n,gear:\n  teeth: 35\n", ("InputError", 3, "after the document's root node"))
write(S, "syntax_unclosed_quote.yaml", 'name: "unterminated\n' + GEAR, ("InputError", -1, "gear"))
write(S, "wrong_type_teeth_text.yaml", gear(teeth="many"), ("InputError", 3, "gear.teeth"))
write(S, "wrong_type_teeth_fraction.yaml", gear(teeth="35.5"), ("InputError", 3, "not a whole number"))
write(S, "wrong_type_gear_is_list.yaml", "gear: [14, 35, 20]\n", ("InputError", 1, "expected a map"))
write(S, "wrong_type_module_is_map.yaml", gear(normal_module_mm="{value: 14}"), ("InputError", 2, "gear.normal_module_mm"))
write(S, "wrong_type_top_is_scalar.yaml", "just a string\n", ("InputError", -1, "expected a map"))
write(S, "nan_module.yaml", gear(normal_module_mm=".nan"), ("InputError", 2, "gear.normal_module_mm"))
write(S, "nan_plain_module.yaml", gear(normal_module_mm="nan"), ("InputError", 2, "gear.normal_module_mm"))
write(S, "inf_face_width.yaml", gear(face_width_mm=".inf"), ("InputError", 7, "gear.face_width_mm"))
write(S, "inf_negative_helix.yaml", gear(helix_angle_deg="-.inf"), ("InputError", 5, "gear.helix_angle_deg"))
write(S, "nan_stroke.yaml", GEAR + "machine:\n  strokes: {x_mm: [0, nan]}\n", ("InputError", 9, "machine.strokes.x_mm"))
write(S, "nan_constant.yaml", GEAR + "machine:\n  constants:\n    S_xy_urad: .nan\n", ("InputError", 10, "S_xy_urad"))
write(S, "nan_polynomial.yaml", GEAR + "machine:\n  polynomials:\n    delta_xx: {unit: um, position_unit: mm, coefficients: [0, nan]}\n",
      ("InputError", -1, "coefficients"))
write(S, "nan_effect_parameter.yaml", GEAR + "effects:\n  - type: thermal_drift\n    x_growth_um: .nan\n", ("InputError", 10, "x_growth_um"))
write(S, "nan_wheel.yaml", GEAR + "wheel:\n  outer_diameter_mm: .NaN\n", ("InputError", 9, "wheel.outer_diameter_mm"))
write(S, "unknown_key_top.yaml", GEAR + "gearbox: 3\n", ("InputError", 8, "unknown key"))
write(S, "unknown_key_typo.yaml", gear(normal_modul_mm="14"), ("InputError", 8, "gear.normal_modul_mm"))
write(S, "unknown_key_measurement.yaml", GEAR + "measurement:\n  rowz: 7\n", ("InputError", 9, "unknown key"))
write(S, "duplicate_key.yaml", GEAR + "  teeth: 36\n", ("InputError", 8, "duplicate key"))
write(S, "huge_module.yaml", gear(normal_module_mm="1e308"), ("InputError", 2, "outside"))
write(S, "huge_overflow_number.yaml", gear(face_width_mm="1e400"), ("InputError", 7, "gear.face_width_mm"))
write(S, "huge_teeth.yaml", gear(teeth="99999999999999999999999"), ("InputError", 3, "gear.teeth"))
write(S, "huge_teeth_in_range.yaml", gear(teeth="10000"), ("InputError", -1, "outside the X stroke"),
      "d ≈ 162 m: refused by the X stroke before the form wheel is synthesised (finding 6)")
write(S, "huge_datum.yaml", GEAR + "machine:\n  datum_face_z_mm: 1e300\n", ("InputError", 9, "machine.datum_face_z_mm"))
write(S, "empty.yaml", "", ("InputError", 0, "empty scene"))
write(S, "only_comments.yaml", "# nothing here\n# at all\n", ("InputError", 0, "empty scene"))
write(S, "only_whitespace.yaml", "   \n\n  \n", ("InputError", 0, "empty scene"))
write(S, "binary_junk.yaml", junk, ("InputError", -1, ""))
write(S, "nul_bytes.yaml", GEAR.encode()[:40] + b"\x00\x00\x00" + GEAR.encode()[40:], ("InputError", -1, ""))
write(S, "deeply_nested_lists.yaml", GEAR + "name: " + "[" * 5000 + "]" * 5000 + "\n", ("InputError", -1, "nested deeper than"))
write(S, "deeply_nested_maps.yaml", GEAR + "name: " + "{a: " * 5000 + "1" + "}" * 5000 + "\n", ("InputError", -1, "nested deeper than"))
write(S, "deeply_nested_block.yaml", GEAR + "measurement:\n" + "".join(" " * (i + 2) + f"k{i}:\n" for i in range(300)),
      ("InputError", 9, "unknown key"))
write(S, "long_line_number.yaml", gear(normal_module_mm="1" * 65_536), ("InputError", 2, "gear.normal_module_mm"))
# YAML limits implicit keys to 1024 characters: a syntax error.
write(S, "long_line_key.yaml", GEAR + "x" * 65_536 + ": 1\n", ("InputError", 8, "YAML syntax error"))
write(S, "teeth_4.yaml", gear(teeth="4"), ("InputError", 3, "gear.teeth"))
write(S, "teeth_negative.yaml", gear(teeth="-35"), ("InputError", 3, "internal gear"))
write(S, "helix_45.yaml", gear(helix_angle_deg="45"), ("InputError", -1, "helix"))
write(S, "helix_minus_50.yaml", gear(helix_angle_deg="-50"), ("InputError", 5, "gear.helix_angle_deg"))
write(S, "hand_contradicts_helix.yaml", gear(hand="left"), ("InputError", 8, "gear.hand"))
write(S, "module_0.yaml", gear(normal_module_mm="0"), ("InputError", 2, "gear.normal_module_mm"))
write(S, "module_negative.yaml", gear(normal_module_mm="-14"), ("InputError", 2, "gear.normal_module_mm"))
write(S, "undercut.yaml", gear(teeth="8", helix_angle_deg="0", profile_shift="-0.5"), ("InputError", -1, "undercut"))
write(S, "pointed_tip.yaml", gear(tip_diameter_mm="625"), ("InputError", 8, "pointed-tip"))
write(S, "root_above_form.yaml", gear(root_diameter_mm="560"), ("InputError", -1, "gear.root_diameter_mm"))
write(S, "missing_gear.yaml", "name: no gear\n", ("InputError", -1, "gear"))
write(S, "missing_teeth.yaml", gear(teeth=None), ("InputError", -1, "gear.teeth"))
write(S, "table_one_point.yaml", GEAR + "machine:\n  tables: [../error_tables/one_point.csv]\n", ("InputError", -1, "one_point.csv"))
write(S, "table_c_not_closed.yaml", GEAR + "machine:\n  tables: [../error_tables/c_not_closed.csv]\n", ("InputError", -1, "c_not_closed.csv"))
write(S, "table_missing_file.yaml", GEAR + "machine:\n  tables: [../error_tables/no_such_table.csv]\n", ("InputError", -1, "no_such_table.csv"))
write(S, "table_binary.yaml", GEAR + "machine:\n  tables: [../error_tables/binary_junk.csv]\n", ("InputError", -1, "binary_junk.csv"))
write(S, "table_short_stroke.yaml", GEAR + "machine:\n  tables: [../error_tables/x_short.csv]\n", ("InputError", -1, "x_short.csv"))
write(S, "grid_rows_1.yaml", GEAR + "measurement:\n  rows: 1\n", ("InputError", 9, "measurement.rows"))
write(S, "grid_huge_1e10.yaml", GEAR + "measurement:\n  dense_rows: 100000\n  dense_cols: 100000\n", ("InputError", 9, "measurement.dense_rows"))
# 10000 × 10000 = 1e8 points per flank (7e9 for 70 flanks, ~336 GB of GridPoint). Accepted until 2026-11-21; then
# refused by the product (grinding::kMaxPointsPerFlank = 4e6); since dense_rows/dense_cols have --dense's bound of
# 1000 (limits::kMaxGridLines) each size alone is refused first, and the product cannot pass 2e6.
write(S, "grid_dense_1e8_per_flank.yaml", GEAR + "measurement:\n  dense_rows: 10000\n  dense_cols: 10000\n",
      ("InputError", 9, "dense_rows: 10000 is outside [2, 1000]"), "the reader must bound dense_rows x dense_cols")
write(S, "grid_dense_just_over_4e6.yaml", GEAR + "measurement:\n  rows: 1000\n  cols: 1000\n  dense_rows: 2000\n  dense_cols: 1501\n",
      ("InputError", -1, "dense_rows: 2000 is outside [2, 1000]"))
write(S, "grid_dense_one_side.yaml", GEAR + "measurement:\n  dense_rows: 50\n", ("InputError", -1, "dense_cols"))
write(S, "grid_tooth_36.yaml", GEAR + "measurement:\n  teeth: [1, 36]\n", ("InputError", 9, "measurement.teeth"))
write(S, "process_first_space_36.yaml", GEAR + "process:\n  first_space: 36\n", ("InputError", -1, "first_space"))
write(S, "process_index_step_not_coprime.yaml", GEAR + "process:\n  index_step: 5\n", ("InputError", -1, "index_step"))
# Issue 18: a denormal feed is inside (0, 1e5] but makes every stroke time infinite (crashed run/report/diagnose).
write(S, "process_feed_denormal.yaml", GEAR + "process:\n  feed_mm_per_min: 1e-320\n", ("InputError", 9, "process.feed_mm_per_min"))
write(S, "process_feed_tiny.yaml", GEAR + "process:\n  feed_mm_per_min: 1e-308\n", ("InputError", 9, "process.feed_mm_per_min"))
write(S, "two_documents.yaml", GEAR + "---\n" + GEAR.replace("teeth: 35", "teeth: 36"), ("InputError", -1, "second YAML document"))
write(S, "measured_empty.yaml", GEAR + "measurement:\n  measured: ''\n", ("InputError", 9, "measurement.measured"))
write(S, "dressing_fraction.yaml", GEAR + "effects:\n  - type: wheel_wear\n    dressing_interval_strokes: 2.5\n",
      ("InputError", 10, "not a whole number"))
write(S, "process_feed_0.yaml", GEAR + "process:\n  feed_mm_per_min: 0\n", ("InputError", 9, "process.feed_mm_per_min"))
write(S, "process_stroke_sideways.yaml", GEAR + "process:\n  stroke: sideways\n", ("InputError", 9, "process.stroke"))
write(S, "effect_unknown.yaml", GEAR + "effects:\n  - type: gremlins\n", ("InputError", 9, "effects[0].type"))
write(S, "effect_twice.yaml", GEAR + "effects:\n  - type: wheel_wear\n  - type: wheel_wear\n", ("InputError", 10, "listed twice"))
write(S, "effects_not_a_list.yaml", GEAR + "effects: thermal_drift\n", ("InputError", 8, "effects"))
write(S, "strokes_reversed.yaml", GEAR + "machine:\n  strokes: {z_mm: [800, 0]}\n", ("InputError", 9, "machine.strokes.z_mm"))
write(S, "wheel_too_small.yaml", GEAR + "wheel:\n  outer_diameter_mm: 5\n", ("InputError", 9, "wheel.outer_diameter_mm"))
write(S, "bom_crlf_nan.yaml", b"\xef\xbb\xbf" + gear(normal_module_mm=".nan").replace("\n", "\r\n").encode(), ("InputError", 2, "gear.normal_module_mm"))
write(S, "component_unknown.yaml", GEAR + "machine:\n  constants:\n    S_xq_urad: 3\n", ("InputError", 10, "S_xq"))
# Issue 30: lists refuse duplicates in the CLI's words (`--teeth 1,1`: "tooth 1 is listed twice"), at the item.
write(S, "teeth_listed_twice.yaml", GEAR + "measurement:\n  teeth: [1, 1, 1, 1, 1, 1, 1, 1, 1]\n",
      ("InputError", 9, "tooth 1 is listed twice"))
write(S, "table_listed_twice.yaml", GEAR + "machine:\n  tables: [../error_tables/x_short.csv, ../error_tables/x_short.csv]\n",
      ("InputError", 9, "table ../error_tables/x_short.csv is listed twice"))
write(S, "assumed_listed_twice.yaml", gear(assumed="[face_width_mm, face_width_mm]"), ("InputError", 8, "'face_width_mm' is listed twice"))
# Issue 30: a denormal or tiny dimension is below the smallest length a part can have (1 µm), and the bound is named.
write(S, "face_width_denormal.yaml", gear(face_width_mm="1e-320"), ("InputError", 7, "is outside [0.001, 5000]: below 0.001 mm (1 µm)"))
write(S, "module_denormal.yaml", gear(normal_module_mm="4.9e-324"), ("InputError", 2, "is outside [0.001, 100]: below 0.001 mm (1 µm)"))
write(S, "tip_diameter_tiny.yaml", gear(tip_diameter_mm="1e-300"), ("InputError", 8, "gear.tip_diameter_mm: 1e-300 is outside [0.001, 50000]"))
write(S, "root_form_denormal.yaml", gear(root_form_diameter_mm="2e-310"), ("InputError", 8, "below 0.001 mm (1 µm)"))
write(S, "probe_diameter_denormal.yaml", GEAR + "report:\n  probe_diameter_mm: 1e-320\n", ("InputError", 9, "report.probe_diameter_mm"))
# Issue 30: a YAML alias gives the wheel the gear's module: a 14 mm wheel for a 14 mm module (tooth depth h ≈ 31.5 mm)
# would carry a profile deeper than its own radius. Refused when the scene is read, so `gear` refuses it too.
write(S, "wheel_alias_module.yaml", gear(normal_module_mm="&m 14") + "wheel:\n  outer_diameter_mm: *m\n",
      ("InputError", 9, "must exceed 4h"))

# ---------------------------------------------------------------------------------------------------- error tables
# expected: (exception, line, fragment)
E = "error_tables"
HX = "x_mm,delta_xx_um,delta_yx_um\n"
def xrows(n=10, step=100.0):
    return "".join(f"{i * step:g},{0.1 * i:.4f},{-0.05 * i:.4f}\n" for i in range(n))
write(E, "one_point.csv", "# one row only\n" + HX + "0,1.0,2.0\n", ("InputError", 3, "at least 2"))
C_HEAD = "c_deg,delta_xc_um,delta_yc_um\n"
write(E, "c_not_closed.csv", C_HEAD + "".join(f"{a},{1 + a / 100:.3f},0\n" for a in range(0, 360, 30)), ("InputError", -1, "c_deg"))
write(E, "c_values_differ.csv", C_HEAD + "".join(f"{a},{1 + a / 100:.3f},0\n" for a in range(0, 361, 30)), ("InputError", -1, "delta_xc_um"))
write(E, "c_half_turn.csv", C_HEAD + "".join(f"{a},1,0\n" for a in range(0, 181, 30)), ("InputError", -1, "c_deg"))
write(E, "truncated_line.csv", HX + xrows(3) + "300,0.3\n" + xrows(2), ("InputError", 5, ""))
write(E, "truncated_file.csv", HX + xrows(3) + "300,0.", ("InputError", 5, ""))
write(E, "extra_field.csv", HX + "0,0,0\n100,1,1,1\n", ("InputError", 3, ""))
write(E, "nan_value.csv", HX + xrows(2) + "200,nan,0\n", ("InputError", 4, "delta_xx_um"))
write(E, "inf_value.csv", HX + xrows(2) + "200,0,-inf\n", ("InputError", 4, "delta_yx_um"))
write(E, "nan_position.csv", HX + "0,0,0\nNaN,1,1\n", ("InputError", 3, "x_mm"))
write(E, "huge_value.csv", HX + "0,0,0\n100,1e400,0\n", ("InputError", 3, "delta_xx_um"))
# Issue 18: finite but not a geometric error of an axis (a wrong unit): |δ| ≤ 1 mm, |ε| ≤ 10 mrad.
write(E, "value_1e12_um.csv", HX + "0,0,0\n100,1e12,0\n", ("InputError", 3, "delta_xx_um"))
write(E, "angle_20_mrad.csv", "a_deg,epsilon_xa_urad\n-30,0\n30,20000\n", ("InputError", 3, "beyond ±10 mrad"))
write(E, "wrong_header.csv", "q_mm,delta_xx_um\n0,0\n100,1\n", ("InputError", 1, "q_mm"))
write(E, "no_header_numbers_first.csv", "0,0,0\n100,1,1\n", ("InputError", 1, ""))
write(E, "unknown_component.csv", "x_mm,delta_qq_um\n0,0\n100,1\n", ("InputError", 1, "delta_qq"))
write(E, "component_of_other_axis.csv", "x_mm,delta_xz_um\n0,0\n100,1\n", ("InputError", 1, "delta_xz_um"))
write(E, "unknown_unit.csv", "x_mm,delta_xx_furlong\n0,0\n100,1\n", ("InputError", 1, "furlong"))
write(E, "duplicate_column.csv", "x_mm,delta_xx_um,delta_xx_nm\n0,0,0\n100,1,1\n", ("InputError", 1, "delta_xx_nm"))
write(E, "duplicate_position.csv", HX + "0,0,0\n100,1,1\n100,2,2\n200,3,3\n", ("InputError", 4, "x_mm"))
write(E, "decreasing_positions.csv", HX + "0,0,0\n200,1,1\n100,2,2\n", ("InputError", 4, "x_mm"))
write(E, "empty.csv", "", ("InputError", 0, "no header"))
write(E, "only_comments.csv", "# a comment\n\n# another\n", ("InputError", 0, "no header"))
write(E, "only_header.csv", HX, ("InputError", -1, ""))
write(E, "empty_field.csv", HX + "0,,0\n100,1,1\n", ("InputError", 2, "empty field"))
write(E, "text_value.csv", HX + "0,zero,0\n100,1,1\n", ("InputError", 2, "delta_xx_um"))
write(E, "bom_crlf_nan.csv", b"\xef\xbb\xbf" + (HX + xrows(2) + "200,NaN,0\n").replace("\n", "\r\n").encode(), ("InputError", 4, ""))
write(E, "binary_junk.csv", junk, ("InputError", -1, ""))
write(E, "long_line.csv", HX + "0," + "1" * 65_536 + ",0\n100,1,1\n", ("InputError", 2, "delta_xx_um"))
write(E, "x_short.csv", HX + xrows(3), ("InputError", -1, ""))  # valid table, but covers only X 0..200: the scene refuses it

# ---------------------------------------------------------------------------------------------------- topology CSV
T = "topology"
TH = "tooth,flank,row,col,diameter_mm,z_mm,deviation_um\n"
def trows(n=4):
    return "".join(f"1,left,{1 + i // 2},{1 + i % 2},{560 + i:.3f},{10 + 20 * (i % 2):.3f},{0.5 * i:.4f}\n" for i in range(n))
write(T, "wrong_header.csv", "tooth,side,row,col,diameter_mm,z_mm,deviation_um\n" + trows(), ("InputError", 1, "header"))
write(T, "reordered_header.csv", "flank,tooth,row,col,diameter_mm,z_mm,deviation_um\n" + trows(), ("InputError", 1, "header"))
write(T, "extra_header_column.csv", TH.rstrip("\n") + ",note\n" + trows(), ("InputError", 1, "note"))
write(T, "missing_header.csv", trows(), ("InputError", 1, "header"))
write(T, "truncated_line.csv", TH + trows(2) + "1,left,2,1,562.0\n", ("InputError", 4, "fields"))
# Cut in the middle of the 6th field, no final newline. (A cut that leaves a number, e.g. "0.1234" → "0.", cannot be
# told from a complete file unless a final newline is required: docs/robustness.md, "Findings".)
write(T, "truncated_file.csv", TH + trows(2) + "1,left,2,1,562.0,1", ("InputError", 4, "fields"))
write(T, "nan_deviation.csv", TH + trows(2) + "1,left,2,1,562.0,10.0,nan\n", ("InputError", 4, "deviation_um"))
# Issue 18: a finite but absurd deviation (1e300 µm crashed diagnose; 1e12 µm is a wrong unit) is refused at its line.
write(T, "huge_deviation.csv", TH + trows(2) + "1,left,2,1,562.0,10.0,1e300\n", ("InputError", 4, "deviation_um"))
write(T, "traces_huge_deviation.csv", "tooth,flank,trace,roll_length_mm,diameter_mm,z_mm,deviation_um\n1,left,helix,10,560,75,1e12\n",
      ("InputError", 2, "deviation_um"))
write(T, "inf_z.csv", TH + trows(2) + "1,left,2,1,562.0,inf,0.1\n", ("InputError", 4, "z_mm"))
write(T, "negative_diameter.csv", TH + "1,left,1,1,-560,10,0.1\n", ("InputError", 2, "diameter_mm"))
write(T, "duplicate_point.csv", TH + trows(3) + "1,left,1,1,560.0,10.0,0.7\n", ("InputError", 5, "duplicate"))
write(T, "unknown_flank.csv", TH + "1,middle,1,1,560,10,0.1\n", ("InputError", 2, "flank"))
write(T, "tooth_0.csv", TH + "0,left,1,1,560,10,0.1\n", ("InputError", 2, "tooth"))
write(T, "tooth_36.csv", TH + "36,right,1,1,560,10,0.1\n", ("InputError", 2, "tooth"))
write(T, "tooth_fraction.csv", TH + "1.5,right,1,1,560,10,0.1\n", ("InputError", 2, "tooth"))
write(T, "tooth_overflow.csv", TH + "99999999999999999999,right,1,1,560,10,0.1\n", ("InputError", 2, "tooth"))
write(T, "row_0.csv", TH + "1,left,0,1,560,10,0.1\n", ("InputError", 2, "row"))
write(T, "empty.csv", "", ("InputError", -1, "header"))
write(T, "only_header.csv", TH, ("InputError", -1, "no data rows"))
write(T, "bom_crlf_nan.csv", b"\xef\xbb\xbf" + (TH + trows(2) + "1,left,2,1,562.0,10.0,NaN\n").replace("\n", "\r\n").encode(),
      ("InputError", 4, "deviation_um"))
write(T, "crlf_nan.csv", (TH + trows(2) + "1,left,2,1,562.0,10.0,NaN\n").replace("\n", "\r\n"), ("InputError", 4, "deviation_um"))
write(T, "binary_junk.csv", junk, ("InputError", -1, ""))
write(T, "long_line.csv", TH + "1,left,1,1,560,10," + "9" * 65_536 + "\n", ("InputError", -1, ""))
write(T, "off_the_flank.csv", TH + "1,left,1,1,700,10,0.1\n", ("InputError", 2, "diameter"))  # read_measurement only
write(T, "traces_unknown_trace.csv", "tooth,flank,trace,roll_length_mm,diameter_mm,z_mm,deviation_um\n1,left,lead,10,560,75,0.1\n",
      ("InputError", 2, "trace"))
write(T, "traces_not_increasing.csv", "tooth,flank,trace,roll_length_mm,diameter_mm,z_mm,deviation_um\n"
      "1,left,profile,10,560,75,0.1\n1,left,profile,20,565,75,0.1\n1,left,profile,15,563,75,0.1\n", ("InputError", 4, "roll_length_mm"))
write(T, "traces_nan.csv", "tooth,flank,trace,roll_length_mm,diameter_mm,z_mm,deviation_um\n1,left,helix,10,560,nan,0.1\n",
      ("InputError", 2, "z_mm"))

# ---------------------------------------------------------------------------------------------------- point clouds
P = "point_clouds"
PH = "x_mm,y_mm,z_mm\n"
def prows(n=4):
    return "".join(f"{280 + i:.3f},{5 * i:.3f},{10 + i:.3f}\n" for i in range(n))
write(P, "wrong_header.csv", "x,y,z\n" + prows(), ("InputError", 1, "header"))
write(P, "missing_header.csv", prows(), ("InputError", 1, "header"))
write(P, "truncated_line.csv", PH + prows(2) + "290.0,3.0\n", ("InputError", 4, ""))
write(P, "truncated_file.csv", PH + prows(2) + "290.0,3.0,", ("InputError", 4, ""))
write(P, "extra_field.csv", PH + prows(2) + "290,3,4,5\n", ("InputError", 4, ""))
write(P, "nan.csv", PH + prows(2) + "290,nan,4\n", ("InputError", 4, "y_mm"))
write(P, "inf.csv", PH + prows(2) + "290,3,-inf\n", ("InputError", 4, "z_mm"))
write(P, "huge_overflow.csv", PH + prows(2) + "1e400,3,4\n", ("InputError", 4, "x_mm"))
# Issue 31: a 1e300 coordinate reached diagnose as "noise level σ = inf µm", no file named; refused at reading.
write(P, "coordinate_1e300.csv", PH + prows(2) + "290,1e300,4\n", ("InputError", 4, "'1e300' mm is beyond ±100000 mm"))
write(P, "duplicate_point.csv", PH + prows(3) + "280.000,0.000,10.000\n", ("InputError", 5, "line 2"))
write(P, "duplicate_id.csv", "x_mm,y_mm,z_mm,id\n1,2,3,7\n4,5,6,7\n", ("InputError", 3, "id"))
write(P, "negative_id.csv", "x_mm,y_mm,z_mm,id\n1,2,3,-1\n", ("InputError", 2, "id"))
write(P, "fractional_id.csv", "x_mm,y_mm,z_mm,id\n1,2,3,1.5\n", ("InputError", 2, "id"))
write(P, "empty.csv", "", ("InputError", -1, ""))
write(P, "only_header.csv", PH, ("InputError", -1, ""))
write(P, "only_comments.csv", "# scanner export\n\n", ("InputError", -1, ""))
write(P, "bom_crlf_nan.csv", b"\xef\xbb\xbf" + (PH + prows(2) + "290,NaN,4\n").replace("\n", "\r\n").encode(), ("InputError", 4, "y_mm"))
write(P, "binary_junk.csv", junk, ("InputError", -1, ""))
write(P, "nul_in_number.csv", PH.encode() + b"280.0,0\x00.5,10\n", ("InputError", 2, "y_mm"))
write(P, "long_line.csv", PH + "1," + "2" * 65_536 + ",3\n", ("InputError", 2, ""))
write(P, "semicolons.csv", "x_mm;y_mm;z_mm\n1;2;3\n", ("InputError", 1, "header"))

# ---------------------------------------------------------------------------------------------------- shards
# Monte Carlo partial results (compensate --shard i/n, docs/monte-carlo.md) as `merge` reads them. Each file is shard
# 2/2 of a run of 4 samples, seed 7; the test reads it (pipeline::read_run_csv) and merges it with
# shards/reference/part_1_of_2.csv (samples 0 and 1): the file must be refused by one or the other, naming it.
M = "shards"
NAMES = ["F_alpha_um", "F_alpha_class", "overall_class", "largest_abs_um", "thickness_um"]
FINGERPRINT = "0123456789abcdef"
def shard(rows, total=4, seed="7", fingerprint=FINGERPRINT, names=NAMES, extra=""):
    head = (f"# geartopo Monte Carlo partial result (docs/monte-carlo.md); merge with: geartopo merge\n"
            f"# samples_total: {total}\n# seed: {seed}\n# iso_direction: transverse\n# helix_slope_sign: helix-angle\n"
            f"# probe_noise_um: 0\n# sampling: linear\n# sampling_reason: checked\n# linear_check_samples: 4\n"
            f"# linear_check_points_um: 0.01\n# linear_check_quantities_um: 0.002\n")
    if fingerprint is not None:
        head += f"# scene_fingerprint: {fingerprint}\n"
    head += extra
    head += "sample," + ",".join("before." + n for n in names) + "," + ",".join("after." + n for n in names) + "\n"
    return head + "".join(r + "\n" for r in rows)
def row(k, before="12.5,7,7,20.1,-1.5", after="3.25,4,5,6.5,0.25"):
    return f"{k},{before},{after}"
os.makedirs(os.path.join(HERE, M, "reference"), exist_ok=True)
with open(os.path.join(HERE, M, "reference", "part_1_of_2.csv"), "w", newline="") as f:
    f.write(shard([row(0), row(1, after="3.5,4,5,6.75,0.5")]))
# The lines: 12 comment lines (11 without a fingerprint), the header on 13, samples from 14.
write(M, "value_1e300.csv", shard([row(2, before="1e300,7,7,20.1,-1.5"), row(3)]), ("InputError", 14, "beyond ±10000 µm"))
write(M, "negative_total_deviation.csv", shard([row(2), row(3, after="-3.25,4,5,6.5,0.25")]),
      ("InputError", 15, "after.F_alpha_um: -3.25 µm is negative: an ISO deviation or largest |deviation| is a magnitude"))
write(M, "class_99.csv", shard([row(2, after="3.25,99,5,6.5,0.25"), row(3)]),
      ("InputError", 14, "after.F_alpha_class: 99 is not a class of ISO 1328-1: a whole number of 1 … 11"))
write(M, "class_0.csv", shard([row(2, before="12.5,7,0,20.1,-1.5"), row(3)]), ("InputError", 14, "before.overall_class: 0 is not a class"))
write(M, "class_1_5.csv", shard([row(2, after="3.25,1.5,5,6.5,0.25"), row(3)]), ("InputError", 14, "after.F_alpha_class: 1.5 is not a class"))
write(M, "class_fraction.csv", shard([row(2, before="12.5,6.5,7,20.1,-1.5"), row(3)]), ("InputError", 14, "6.5 is not a class"))
write(M, "largest_abs_negative.csv", shard([row(2, before="12.5,7,7,-20.1,-1.5"), row(3)]), ("InputError", 14, "before.largest_abs_um"))
write(M, "signed_value_huge.csv", shard([row(2), row(3, after="3.25,4,5,6.5,-2e4")]), ("InputError", 15, "after.thickness_um: -2e4 µm is beyond ±10000 µm"))
write(M, "nan_value.csv", shard([row(2, after="nan,4,5,6.5,0.25"), row(3)]), ("InputError", 14, "'nan' is not a finite number"))
write(M, "sample_beyond_run.csv", shard([row(2), row(4)]), ("InputError", 15, "'4' is not a sample number of this run of 4 samples (0 … 3)"))
write(M, "sample_negative.csv", shard([row(-1), row(3)]), ("InputError", 14, "sample number"))
write(M, "samples_not_increasing.csv", shard([row(3), row(2)]), ("InputError", 15, "sample numbers must increase"))
# 2⁶⁴: CLI11 used to wrap it to 0; the reader refuses it as a seed.
write(M, "seed_2_64.csv", shard([row(2), row(3)], seed="18446744073709551616"), ("InputError", 3, "is not a seed: a whole number of 0 … 2⁶⁴ − 1"))
write(M, "seed_negative.csv", shard([row(2), row(3)], seed="-7"), ("InputError", 3, "is not a seed"))
write(M, "unknown_quantity.csv", shard([row(2), row(3)], names=["F_gamma_um"] + NAMES[1:]),
      ("InputError", 13, "'F_gamma_um' is not a quantity geartopo writes"))
write(M, "quantity_twice.csv", shard([row(2), row(3)], names=NAMES[:4] + ["F_alpha_um"]), ("InputError", 13, "'F_alpha_um' is listed twice"))
write(M, "fingerprint_malformed.csv", shard([row(2), row(3)], fingerprint="not-hex"), ("InputError", 12, "16 hex digits"))
# Refused by merge: each file alone is a valid shard, but not of the reference's run; named at its first differing
# setting (file:line: field; a missing one at the header, before which it would stand).
write(M, "seed_differs.csv", shard([row(2), row(3)], seed="8"), ("InputError", 3, "seed: 8 ("))
write(M, "samples_total_differs.csv", shard([row(2), row(3)], total=5), ("InputError", 2, "samples_total: 5 ("))
write(M, "fingerprint_differs.csv", shard([row(2), row(3)], fingerprint="fedcba9876543210"),
      ("InputError", 12, "scene_fingerprint: fedcba9876543210 ("))
write(M, "fingerprint_missing.csv", shard([row(2), row(3)], fingerprint=None), ("InputError", 12, "scene_fingerprint: not recorded ("))
write(M, "names_differ.csv", shard([row(2, before="12.5,7,7,20.1", after="3.25,4,5,6.5"), row(3, before="12.5,7,7,20.1", after="3.25,4,5,6.5")],
                                   names=NAMES[:4]), ("InputError", 13, "header: F_alpha_um,F_alpha_class,overall_class,largest_abs_um ("))
write(M, "sample_in_both.csv", shard([row(1), row(2), row(3)]), ("invalid_argument", 0, "sample 1 is in two parts: part 1 ("))
# Issue 31: a shard of another gear (the reference records none, as shards written before the gear was recorded).
write(M, "gear_differs.csv", shard([row(2), row(3)], extra="# gear: teeth=36 normal_module_mm=14 normal_pressure_angle_deg=20 "
                                   "helix_angle_deg=30 profile_shift=0.274 face_width_mm=150\n"),
      ("InputError", 13, "gear: teeth=36 normal_module_mm=14"))
write(M, "gear_malformed.csv", shard([row(2), row(3)], extra="# gear: 36\n"), ("InputError", 13, "'36' is not a gear record geartopo writes"))

# ---------------------------------------------------------------------------------------------------- Klingelnberg exports
# Read by measurement::read_klingelnberg (docs/measurement-formats.md). The head of tests/measurement/data's example.
K = "exports"
KHEAD = """HEADER KS.MK.FILE
TYPE       STI          ! geartopo robustness corpus
SEPARATOR  :
UNDEFINED  -2147483.648
  21 :Normalmodul mn [mm]...............: 2.0000
  22 :Zähnezahl z.......................: 24
  23 :Schrägungswinkel beta [Grad]......: 15.0000
  24 :Eingriffswinkel alpha n [Grad]....: 20.0000
  26 :Zahnbreite b [mm].................: 20.0000
  41 :Start Messbereich.....da [mm].....: 47.5000     47.5000
  44 :Ende der Messstrecke..de [mm].....: 53.2000     53.2000
  61 :Messanfang............ba [mm].....: 2.0000      2.0000
  64 :Messende..............be [mm].....: 18.0000     18.0000
"""  # 13 lines: the first trace head is line 14
def profile(tooth=1, flank="links", values=".000  1.000  2.000  3.000  4.000", count=5, z="10.0"):
    return f"Profil:  Zahn-Nr.: {tooth} {flank} / {count} Werte / z= {z}\n  {values}\n"
GOOD_REST = profile(1, "rechts", ".000  -.500  -1.0  -1.500  -2.000") + "Flankenlinie: Zahn-Nr.: 2 links / 4 Werte / d= 50.0\n  -1.000  -2.000  -3.000  -4.000\n"
os.makedirs(os.path.join(HERE, K, "reference"), exist_ok=True)
with open(os.path.join(HERE, K, "reference", "good.mka"), "w", newline="") as f:  # the cases' valid twin (3 traces)
    f.write(KHEAD + profile() + GOOD_REST)
# Issue 30: "nan" among the values was reported as "the head announces 5 values, 0 follow".
write(K, "nan_value.mka", KHEAD + profile(values=".000  1.000  nan  3.000  4.000") + GOOD_REST,
      ("InputError", 15, "'nan' is not a number: value 3 of the profile trace of tooth 1 (head at line 14)"))
write(K, "nan_first_value.mka", KHEAD + profile(values="NaN  1.000  2.000  3.000  4.000") + GOOD_REST, ("InputError", 15, "'NaN' is not a number"))
write(K, "inf_value.mka", KHEAD + profile(values=".000  1.000  2.000  -inf  4.000") + GOOD_REST, ("InputError", 15, "'-inf' is not a number"))
write(K, "text_value.mka", KHEAD + profile(values=".000  1.000  n/a  3.000  4.000") + GOOD_REST, ("InputError", 15, "'n/a' is not a number"))
write(K, "huge_value.mka", KHEAD + profile(values=".000  1.000  1e300  3.000  4.000") + GOOD_REST, ("InputError", 15, "beyond ±1000 µm"))
write(K, "value_1e6_um.mka", KHEAD + GOOD_REST + profile(2, "rechts", ".000  1.000  2.000  3.000  1e6"), ("InputError", 19, "1e6 µm is beyond ±1000 µm"))
# Issue 30: tooth 18's blocks written as tooth 1 again: refused (a repeat would count the flank twice in every fit).
write(K, "tooth_measured_twice.mka", KHEAD + profile() + GOOD_REST + profile(1, "links", ".100  1.200  2.100  3.300  4.200"),
      ("InputError", 20, "tooth 1 left profile at z= 10 mm is measured twice (first at line 14)"))
write(K, "topography_line_twice.mka", KHEAD + GOOD_REST + "TOPOGRAFIE: Zahn-Nr.: 2 /Profil:1 rechts / 3 Werte / z= 5.0\n  .046  .046  .046\n"
      "TOPOGRAFIE: Zahn-Nr.: 2 /Profil:2 rechts / 3 Werte / z= 5.0\n  .050  .040  .046\n", ("InputError", 20, "is measured twice (first at line 18)"))
write(K, "too_few_values.mka", KHEAD + profile(values=".000  1.000  2.000") + GOOD_REST, ("InputError", 14, "the head announces 5 values, 3 follow"))
write(K, "too_many_values.mka", KHEAD + profile(values=".000  1.000  2.000  3.000  4.000  5.000") + GOOD_REST,
      ("InputError", 15, "more values than the 5 announced"))
write(K, "tooth_0.mka", KHEAD + profile(tooth=0) + GOOD_REST, ("InputError", 14, "'0' is not a tooth number"))
write(K, "no_flank.mka", KHEAD + profile(flank="mitte") + GOOD_REST, ("InputError", 14, "expected 'links' or 'rechts'"))
write(K, "zero_values.mka", KHEAD + profile(count=0, values="") + GOOD_REST, ("InputError", 14, "'0' is not a number of values"))
write(K, "position_nan.mka", KHEAD + profile(z="nan") + GOOD_REST, ("InputError", 14, "expected a position in mm"))
write(K, "truncated_in_values.mka", KHEAD + GOOD_REST + "Profil:  Zahn-Nr.: 3 links / 5 Werte / z= 10.0\n  .000  1.0", ("InputError", 18, "announces 5 values, 2 follow"))
# Issue 31: as strict as the writers. Ranges must run forwards, each flank (line 11 is de, line 13 be).
write(K, "range_reversed.mka", KHEAD.replace("53.2000     53.2000", "53.2000     47.0000") + profile() + GOOD_REST,
      ("InputError", 11, "the range da … de = 47.5 … 47 mm (right flank) is reversed"))
write(K, "range_empty.mka", KHEAD.replace("18.0000     18.0000", "2.0000      2.0000") + profile() + GOOD_REST,
      ("InputError", 13, "the range ba … be = 2 … 2 mm (left flank) is empty"))
# Header numbers the reader uses: an error, not a warning and an unchecked file.
write(K, "module_unreadable.mka", KHEAD.replace("mn [mm]...............: 2.0000", "mn [mm]...............: zwei") + profile() + GOOD_REST,
      ("InputError", 5, "'zwei' is not a number"))
write(K, "teeth_fraction.mka", KHEAD.replace("z.......................: 24", "z.......................: 24.5") + profile() + GOOD_REST,
      ("InputError", 6, "24.5 is not a number of teeth"))
write(K, "teeth_missing_value.mka", KHEAD.replace("z.......................: 24", "z.......................:") + profile() + GOOD_REST,
      ("InputError", 6, "no value after the label"))
write(K, "range_1e300.mka", KHEAD.replace("47.5000     47.5000", "1e300       47.5000") + profile() + GOOD_REST,
      ("InputError", 10, "1e300 is beyond ±100000"))
write(K, "position_1e300.mka", KHEAD + profile(z="1e300") + GOOD_REST, ("InputError", 14, "1e300 mm is beyond ±100000 mm"))
# Tooth numbers 1 … z (z = 24 from line 6): tooth 10⁹ is an error like tooth 25, "1e9" too (not a tagged block).
write(K, "tooth_beyond_z.mka", KHEAD + profile(tooth=25) + GOOD_REST, ("InputError", 14, "tooth 25 of a gear with 24 teeth"))
write(K, "tooth_1e9_digits.mka", KHEAD + profile(tooth=1000000000) + GOOD_REST, ("InputError", 14, "tooth 1000000000 of a gear with 24 teeth"))
write(K, "tooth_1e9.mka", KHEAD + profile(tooth="1e9") + GOOD_REST, ("InputError", 14, "'1e9' is not a tooth number: a whole number 1 … 24"))
# A bad number named with its column and what is allowed, not "the head announces 5 values, 0 follow".
write(K, "value_dashes.mka", KHEAD + profile(values="--  --  --  --  --") + GOOD_REST,
      ("InputError", 15, "'--' is not a number: value 1 of the profile trace of tooth 1 (head at line 14); numbers are written 1.5"))
write(K, "value_decimal_comma_among_points.mka", KHEAD + profile(values=".000  1.000  2,838  3.000  4.000") + GOOD_REST,
      ("InputError", 15, "'2,838' has a decimal comma, but this file's numbers have a decimal point (the first, '2.0000', at line 5)"))
write(K, "value_inf_word.mka", KHEAD + profile(values="inf  1.000  2.000  3.000  4.000") + GOOD_REST,
      ("InputError", 15, "'inf' is not a number: value 1"))
# Pitch tables (title at line 20, rows from line 22): nan, inf, a value beyond ±1000 µm, a tooth twice or beyond z, each at its place.
def pitch(rows):
    return "linke Zahnflanke\nZahn-Nr.   fp     Fp     Fr\n" + "".join(f"  {r}\n" for r in rows)
write(K, "pitch_nan.mka", KHEAD + profile() + GOOD_REST + pitch(["1      0.662  0.662  0.778", "2      nan   .262  1.100"]),
      ("InputError", 23, "'nan' is not a number: the pitch table's fp of tooth 2 (left flank)"))
write(K, "pitch_inf.mka", KHEAD + profile() + GOOD_REST + pitch(["1      0.662  inf  0.778"]),
      ("InputError", 22, "'inf' is not a number: the pitch table's Fp of tooth 1"))
write(K, "pitch_1e6.mka", KHEAD + profile() + GOOD_REST + pitch(["1      0.662  0.662  1e6"]),
      ("InputError", 22, "1e6 µm is beyond ±1000 µm"))
write(K, "pitch_tooth_twice.mka", KHEAD + profile() + GOOD_REST + pitch(["1      0.662  0.662  0.778", "1      -.400   .262  1.100"]),
      ("InputError", 23, "tooth 1 is in the left pitch table twice (first at line 22)"))
write(K, "pitch_tooth_beyond_z.mka", KHEAD + profile() + GOOD_REST + pitch(["36      0.662  0.662  0.778"]),
      ("InputError", 22, "tooth 36 in the pitch table: a tooth number is 1 … 24"))
# UTF-16 (Windows "Unicode"): named as such, not as a bad header.
GOOD = KHEAD + profile() + GOOD_REST
write(K, "utf16_le_bom.mka", GOOD.encode("utf-16-le").join([b"\xff\xfe", b""]), ("InputError", 0, "the file is UTF-16 (little-endian, byte-order mark FF FE)"))
write(K, "utf16_be_bom.mka", b"\xfe\xff" + GOOD.encode("utf-16-be"), ("InputError", 0, "byte-order mark FE FF), which geartopo does not read: save it as UTF-8 or latin-1"))
write(K, "utf16_no_bom.mka", GOOD.encode("utf-16-le"), ("InputError", 0, "the file is UTF-16 without a byte-order mark"))
# Issue 43: header values the reader accepted silently (a line given twice, angles and widths no gear has, a third
# range value, another mark of undefined points, read as deviations) and a NUL that cut the message short.
write(K, "header_teeth_twice.mka", KHEAD.replace("  23 :", "  22 :Zähnezahl z.......................: 25\n  23 :") + profile() + GOOD_REST,
      ("InputError", 7, "22 Zähnezahl z: given again with other values (first at line 6)"))
write(K, "helix_angle_90.mka", KHEAD.replace("15.0000", "90.0000") + profile() + GOOD_REST,
      ("InputError", 7, "90° is not a helix angle: |β| < 90°"))
write(K, "pressure_angle_0.mka", KHEAD.replace("20.0000\n  26", "0.0000\n  26") + profile() + GOOD_REST,
      ("InputError", 8, "0° is not a normal pressure angle: 0° < α_n < 90°"))
write(K, "face_width_0.mka", KHEAD.replace("b [mm].................: 20.0000", "b [mm].................: 0.0000") + profile() + GOOD_REST,
      ("InputError", 9, "0 mm is not a face width: a length > 0 mm"))
write(K, "range_three_values.mka", KHEAD.replace("47.5000     47.5000", "47.5000     47.5000     47.5000") + profile() + GOOD_REST,
      ("InputError", 10, "3 values: a measuring range has one (both flanks) or two (left, right)"))
write(K, "undefined_other_mark.mka", KHEAD.replace("UNDEFINED  -2147483.648", "UNDEFINED  -999.999") + profile() + GOOD_REST,
      ("InputError", 4, "'-999.999' is not the mark of an undefined point this reader knows (-2147483.648)"))
write(K, "value_nul.mka", KHEAD + profile(values=".000  1.000\0  2.000  3.000  4.000") + GOOD_REST,
      ("InputError", 15, "'1.000\\0' is not a number: value 2 of the profile trace of tooth 1"))

# ---------------------------------------------------------------------------------------------------- predictions
# prediction.json as `evaluate --prediction` reads it (report::read_prediction_json; the keys of report::prediction_json,
# written here by hand). Issue 31: every value checked as merge checks a shard's, keys once, numbers a double holds.
R = "predictions"
GEAR_RECORD = "teeth=35 normal_module_mm=14 normal_pressure_angle_deg=20 helix_angle_deg=30 profile_shift=0.274 face_width_mm=150"
def prediction(quantities=None, top=None, raw_quantities=None):
    q = quantities or {"F_alpha_um": ("12.5, 11.0, 14.0", "3.25, 2.5, 4.0"), "F_alpha_class": ("7, 6, 8", "4, 3, 5")}
    fields = {"samples": "40", "seed": "1", "coverage_probability": "0.95", "gear": f'"{GEAR_RECORD}"',
              "probe_noise_um": "0"}
    fields.update(top or {})
    def band(t):
        m, lo, hi = (x.strip() for x in t.split(","))
        return f'{{"median": {m}, "low": {lo}, "high": {hi}}}'
    body = raw_quantities or ",\n".join(f'    "{n}": {{"before": {band(b)}, "after": {band(a)}}}' for n, (b, a) in q.items())
    return "{\n" + "".join(f'  "{k}": {v},\n' for k, v in fields.items()) + '  "quantities": {\n' + body + "\n  }\n}\n"
os.makedirs(os.path.join(HERE, R, "reference"), exist_ok=True)
with open(os.path.join(HERE, R, "reference", "good.json"), "w", newline="") as f:
    f.write(prediction())
with open(os.path.join(HERE, R, "reference", "other_gear.json"), "w", newline="") as f:  # refused by evaluate, not the reader
    f.write(prediction(top={"gear": '"' + GEAR_RECORD.replace("teeth=35", "teeth=36") + '"'}))
write(R, "negative_um.json", prediction({"F_alpha_um": ("12.5, 11.0, 14.0", "-3.25, -4.0, -2.5")}), ("InputError", 0, "µm is negative"))
write(R, "class_99.json", prediction({"F_alpha_class": ("99, 99, 99", "4, 3, 5")}), ("InputError", 0, "99 is not a class of ISO 1328-1"))
write(R, "class_1_5.json", prediction({"F_alpha_class": ("1.5, 1, 2", "4, 3, 5")}), ("InputError", 0, "1.5 is not a class of ISO 1328-1"))
write(R, "unknown_quantity.json", prediction({"F_gamma_um": ("1, 1, 1", "1, 1, 1")}), ("InputError", 0, "'F_gamma_um' is not a quantity geartopo writes"))
write(R, "coverage_2.json", prediction(top={"coverage_probability": "2"}), ("InputError", 0, "2 is not a probability in (0, 1)"))
write(R, "coverage_0.json", prediction(top={"coverage_probability": "0"}), ("InputError", 0, "0 is not a probability in (0, 1)"))
write(R, "value_1e400.json", prediction({"F_alpha_um": ("1e400, 11.0, 14.0", "3.25, 2.5, 4.0")}),
      ("InputError", 8, "'1e400' is beyond the range of a number"))
write(R, "value_beyond_bound.json", prediction({"F_alpha_um": ("1e300, 1e300, 1e300", "3.25, 2.5, 4.0")}), ("InputError", 0, "beyond ±10000 µm"))
write(R, "duplicate_top_key.json", prediction(top={"samples": "40", "seed": "1"}).replace('"seed": 1,', '"seed": 1,\n  "seed": 2,'),
      ("InputError", 0, "the key 'seed' is given twice"))
write(R, "duplicate_quantity.json", prediction(raw_quantities='    "F_alpha_um": {"before": {"median": 1, "low": 1, "high": 1}, "after": {"median": 1, "low": 1, "high": 1}},\n'
                                                             '    "F_alpha_um": {"before": {"median": 9, "low": 9, "high": 9}, "after": {"median": 9, "low": 9, "high": 9}}'),
      ("InputError", 0, "the key 'F_alpha_um' is given twice in quantities"))
write(R, "duplicate_band_key.json", prediction(raw_quantities='    "F_alpha_um": {"before": {"median": 1, "low": 1, "high": 1, "high": 7}, "after": {"median": 1, "low": 1, "high": 1}}'),
      ("InputError", 0, "the key 'high' is given twice in quantities.F_alpha_um.before"))
write(R, "syntax_error.json", prediction().replace('"samples": 40,', '"samples": 40,,'), ("InputError", 2, "not JSON"))
write(R, "nan_literal.json", prediction({"F_alpha_um": ("NaN, 11.0, 14.0", "3.25, 2.5, 4.0")}), ("InputError", 8, "not JSON"))
write(R, "low_above_high.json", prediction({"F_alpha_um": ("12.5, 15.0, 14.0", "3.25, 2.5, 4.0")}), ("InputError", 0, "does not hold"))
write(R, "seed_negative.json", prediction(top={"seed": "-1"}), ("InputError", 0, "not a seed"))
write(R, "probe_noise_negative.json", prediction(top={"probe_noise_um": "-0.5"}), ("InputError", 0, "is not a σ of 0 … 1000 µm"))
write(R, "gear_malformed.json", prediction(top={"gear": "35"}), ("InputError", 0, "not a gear record geartopo writes"))
write(R, "samples_0.json", prediction(top={"samples": "0"}), ("InputError", 0, "is not a count of samples"))
write(R, "not_an_object.json", "[1, 2, 3]\n", ("InputError", 0, "not a JSON object"))

for folder, rows in ROWS.items():
    with open(os.path.join(HERE, folder, "expected.tsv"), "w") as f:
        f.write("# file\texception\tline (0: none, -1: any)\tmessage fragment\tnote\n")
        for name, exc, line, frag, note in rows:
            f.write(f"{name}\t{exc}\t{line}\t{frag}\t{note}\n")
print({k: len(v) for k, v in ROWS.items()})
