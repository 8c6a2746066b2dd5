#!/usr/bin/env bash
# Every line of tests/mutations.txt still applies: its sed pattern changes its file. A mutation
# whose code moved or changed would otherwise be reported by tools/mutation-check only when it
# runs ("does not apply"), and the suite's proof that it can fail would shrink in silence.
# usage: check_mutations_apply.sh ROOT
set -uo pipefail
root="$1"
tmp=$(mktemp)
trap 'rm -f "$tmp"' EXIT
i=0 bad=0
while IFS='|' read -r file old new what; do
  [ -z "$file" ] && continue
  i=$((i + 1))
  f="$root/engine/src/$file"
  [ -f "$root/$file" ] && f="$root/$file"
  if [ ! -f "$f" ]; then echo "M$i: no file $file ($what)"; bad=$((bad + 1)); continue; fi
  cp "$f" "$tmp"
  sed -i "s|$old|$new|" "$tmp"
  if cmp -s "$f" "$tmp"; then echo "M$i: its pattern no longer matches $file ($what)"; bad=$((bad + 1)); fi
done <"$root/tests/mutations.txt"
[ "$bad" -eq 0 ] && echo "all $i mutations apply"
[ "$bad" -eq 0 ]
