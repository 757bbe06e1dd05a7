#!/usr/bin/env bash
# Keeps the option tables of the docs equal to the options the methods declare in code.
# `penumbra list --markdown` prints one table per method between the markers
#   <!-- options:begin METHOD --> ... <!-- options:end -->
# and every page of docs/ holding such markers gets that table between them.
#   scripts/doc-options.sh [--write] [PENUMBRA_BINARY]
# Without --write it only checks (the ctest `docs.options`): exit 1 with a diff when a page is out
# of date, an unknown method is named, or a method has no table in any page. With --write it
# rewrites the blocks in place.
set -euo pipefail
write=0
if [ "${1:-}" = "--write" ]; then
  write=1
  shift
fi
bin="$(realpath "${1:-./build/release/penumbra}")"
cd "$(dirname "$0")/.."
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
"$bin" list --markdown >"$work/tables.md"

failed=0
pages=()
for page in docs/*.md docs/methods/*.md; do
  grep -q '^<!-- options:begin ' "$page" && pages+=("$page")
done
for page in "${pages[@]}"; do
  new="$work/$(basename "$page").new"
  if ! awk -v tables="$work/tables.md" -v page="$page" '
    function method_of(line) {
      sub(/^<!-- options:begin /, "", line)
      sub(/ -->$/, "", line)
      return line
    }
    BEGIN {
      while ((getline line < tables) > 0) {
        if (line ~ /^<!-- options:begin [^ ]+ -->$/) cur = method_of(line)
        if (cur != "") block[cur] = block[cur] line "\n"
        if (line == "<!-- options:end -->") cur = ""
      }
    }
    /^<!-- options:begin / {
      m = method_of($0)
      if (!(m in block)) {
        print page ": no method `" m "` (penumbra list)" > "/dev/stderr"
        bad = 1
      } else {
        printf "%s", block[m]
      }
      skip = 1
      next
    }
    skip && $0 == "<!-- options:end -->" { skip = 0; next }
    skip { next }
    { print }
    END {
      if (skip) { print page ": options block not closed" > "/dev/stderr"; bad = 1 }
      exit bad
    }' "$page" >"$new"; then
    failed=1
    continue
  fi
  if ! cmp -s "$page" "$new"; then
    if [ "$write" -eq 1 ]; then
      cp "$new" "$page"
      echo "doc-options: $page updated"
    else
      diff -u "$page" "$new" || true
      echo "doc-options: $page: option tables differ from the code (scripts/doc-options.sh --write)"
      failed=1
    fi
  fi
done

# Every method's table is in some page.
while read -r method; do
  if [ ${#pages[@]} -eq 0 ] || ! grep -qx "<!-- options:begin $method -->" "${pages[@]}"; then
    echo "doc-options: no page of docs/ holds <!-- options:begin $method -->"
    failed=1
  fi
done < <(sed -n 's/^<!-- options:begin \([^ ]*\) -->$/\1/p' "$work/tables.md")
exit "$failed"
