#!/usr/bin/env bash
# Lists the functions longer than the project's limit: 150 lines anywhere, 120 in src/diagnosis. Lines are counted
# from a function's first line to its closing brace, as Universal Ctags finds them (C++ and Python under src/,
# include/, gears/, surfaces/, evaluation/, python/); a lambda counts as part of the function it is written in.
#
#   bash scripts/function-lengths.sh            # the folders of the rule; exit 1 when a function is over its limit
#   LIMIT=100 bash scripts/function-lengths.sh  # another limit outside src/diagnosis
set -euo pipefail
cd "$(dirname "$0")/.."
command -v ctags >/dev/null || bash scripts/install-deps.sh universal-ctags
limit=${LIMIT:-150}
diagnosis_limit=${DIAGNOSIS_LIMIT:-120}
ctags -R --languages=C++,Python --kinds-C++=f --kinds-Python=fm --fields=+ne --output-format=json --sort=no -f - \
  src include gears surfaces evaluation python |
  python3 -c '
import json, sys
limit, diagnosis_limit = int(sys.argv[1]), int(sys.argv[2])
over = []
for line in sys.stdin:
    tag = json.loads(line)
    if tag.get("_type") != "tag" or "end" not in tag:
        continue
    n = tag["end"] - tag["line"] + 1
    cap = diagnosis_limit if tag["path"].startswith("src/diagnosis/") else limit
    if n > cap:
        over.append((n, cap, tag["path"], tag["line"], tag.get("scope", ""), tag["name"]))
for n, cap, path, line, scope, name in sorted(over, reverse=True):
    qualified = scope + "::" + name if scope else name
    print(f"{n:4d} lines (limit {cap})  {path}:{line}  {qualified}")
print(f"{len(over)} function(s) over the limit", file=sys.stderr)
sys.exit(1 if over else 0)
' "$limit" "$diagnosis_limit"
