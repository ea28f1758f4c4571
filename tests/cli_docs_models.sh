#!/usr/bin/env bash
# docs/models.md stays in step with the registry: every model, option, option value and
# parameter (of every option value) that `brdfit models --json` lists is named on that
# page in backquotes, and the page's table of models lists exactly the registered ones.
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need jq jq

doc="$(dirname "$0")/../docs/models.md"
[ -r "$doc" ] && ok || { bad "no $doc"; finish; exit; }
"$BRDFIT" models --json > "$tmp/models.json" && ok || bad "brdfit models --json failed"

named() { # what, name: `name` must appear on the page
  grep -qF -- "\`$2\`" "$doc" && ok || bad "docs/models.md does not name $1 \`$2\`"
}

while read -r m; do
  named model "$m"
  grep -qE "^##+ ($m( |:|$)|.* and $m$)" "$doc" && ok || bad "docs/models.md has no section for $m"
done < <(jq -r '.models[].name' "$tmp/models.json")

while read -r m p; do
  named "parameter of $m" "$p"
done < <(jq -r '.models[] | .name as $m | .params[] | "\($m) \(.name)"' "$tmp/models.json")

while read -r m o v; do
  named "option of $m" "$o"
  named "value of $m's option $o" "$v"
done < <(jq -r '.models[] | .name as $m | .options[] | .name as $o | .values[] | "\($m) \($o) \(.value)"' \
           "$tmp/models.json")

while read -r m p; do
  named "parameter of a variant of $m" "$p"
done < <(jq -r '.models[] | .name as $m | .options[].values[].params[] | "\($m) \(.)"' "$tmp/models.json" | sort -u)

# The summary table lists the registered models, no more and no fewer.
jq -r '.models[].name' "$tmp/models.json" | sort > "$tmp/registered"
grep -oE '^\| \[`[a-z_]+`\]' "$doc" | sed -E 's/^\| \[`([a-z_]+)`\]/\1/' | sort > "$tmp/listed"
diff "$tmp/registered" "$tmp/listed" > "$tmp/diff" && ok ||
  bad "docs/models.md's table of models differs from brdfit models: $(tr '\n' ' ' < "$tmp/diff")"

finish
