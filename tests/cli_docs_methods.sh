#!/usr/bin/env bash
# docs/methods.md names every method of the registry (brdfit methods --json) with its
# back end's section, so the page cannot fall behind the table.
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need jq jq
doc=$(dirname "$0")/../docs/methods.md
"$BRDFIT" methods --json > "$tmp/m.json" || bad "brdfit methods --json failed"
n=$(jq '.methods | length' "$tmp/m.json")
[ "$n" -ge 13 ] && ok || bad "only $n methods"
for k in $(seq 0 $((n - 1))); do
  name=$(jq -r ".methods[$k].name" "$tmp/m.json")
  backend=$(jq -r ".methods[$k].backend" "$tmp/m.json")
  # The method's row sits under its back end's heading.
  section=$(awk -v b="--backend $backend" '/^## / { on = index($0, b) > 0 } on' "$doc")
  grep -q "^| \`$name\`" <<<"$section" && ok || bad "docs/methods.md has no row for $backend method $name"
done
# Constrained methods are marked so in the NLopt table.
for name in $(jq -r '.methods[] | select(.backend == "nlopt" and (.capabilities | index("constraints"))) | .name' "$tmp/m.json"); do
  grep -q "^| \`$name\`.*| yes |" "$doc" && ok || bad "$name takes constraints; the page does not say so"
done
finish
