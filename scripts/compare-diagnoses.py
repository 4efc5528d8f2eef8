#!/usr/bin/env python3
"""Compares two golden sets of diagnoses (folders of diagnosis.json dumps, scripts/diagnosis-golden.sh).

Usage: compare-diagnoses.py BEFORE AFTER [--rel 1e-6] [--abs 1e-9] [--ignore KEY ...]

Numbers agree when |a - b| <= abs + rel * max(|a|, |b|) (print precision: the files print 6 significant digits at
most); strings, booleans and nulls must be equal; keys present in BEFORE must be in AFTER (AFTER may add keys: new
records). Prints every difference with its JSON path and exits 1 if there is any, or if a dump is missing.
"""
import argparse
import json
import math
import pathlib
import sys


def walk(a, b, path, opts, out):
    if isinstance(a, dict):
        if not isinstance(b, dict):
            out.append(f"{path}: object became {type(b).__name__}")
            return
        for k in a:
            if k in opts.ignore:
                continue
            if k not in b:
                out.append(f"{path}.{k}: missing")
            else:
                walk(a[k], b[k], f"{path}.{k}", opts, out)
    elif isinstance(a, list):
        if not isinstance(b, list) or len(a) != len(b):
            out.append(f"{path}: list of {len(a)} became {len(b) if isinstance(b, list) else type(b).__name__}")
            return
        for i, (x, y) in enumerate(zip(a, b)):
            walk(x, y, f"{path}[{i}]", opts, out)
    elif isinstance(a, bool) or a is None or isinstance(a, str):
        if a != b:
            out.append(f"{path}: {a!r} became {b!r}")
    elif isinstance(a, (int, float)):
        if not isinstance(b, (int, float)) or isinstance(b, bool):
            out.append(f"{path}: {a!r} became {b!r}")
        elif not (math.isclose(a, b, rel_tol=opts.rel, abs_tol=opts.abs) or (math.isinf(a) and a == b)):
            out.append(f"{path}: {a!r} became {b!r}")
    else:
        out.append(f"{path}: unexpected {type(a).__name__}")


def main():
    p = argparse.ArgumentParser()
    p.add_argument("before")
    p.add_argument("after")
    p.add_argument("--rel", type=float, default=1e-6)
    p.add_argument("--abs", type=float, default=1e-9)
    p.add_argument("--ignore", nargs="*", default=[])
    opts = p.parse_args()
    before, after = pathlib.Path(opts.before), pathlib.Path(opts.after)
    names = sorted(f.name for f in before.glob("*.json"))
    bad = 0
    for name in names:
        other = after / name
        if not other.exists():
            print(f"{name}: missing in {after}")
            bad += 1
            continue
        out = []
        walk(json.loads((before / name).read_text()), json.loads(other.read_text()), "$", opts, out)
        if out:
            bad += 1
            print(f"{name}: {len(out)} difference(s)")
            for line in out[:20]:
                print("   ", line)
    extra = sorted(set(f.name for f in after.glob("*.json")) - set(names))
    for name in extra:
        print(f"{name}: new in {after}")
    print(f"{len(names)} diagnoses compared, {bad} differ, {len(extra)} new")
    sys.exit(1 if bad or extra else 0)


if __name__ == "__main__":
    main()
