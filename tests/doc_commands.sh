#!/usr/bin/env bash
# Runs every `ecoterra ...` line of the code blocks of README.md and docs/user-guide.md as written,
# in order, in a fresh folder per document (with data/ linked in and the built program first on
# PATH), so that the documented commands cannot go stale. Usage: doc_commands.sh BUILD_DIR ROOT
set -euo pipefail
build="$1"
root="$2"
for doc in README.md docs/user-guide.md; do
  dir="$(mktemp -d)"
  ln -s "$root/data" "$dir/data"
  # Lines inside ``` blocks, continuation lines joined, the ecoterra commands, trailing comments
  # (two or more spaces, then #) removed.
  awk '/^```/ { inside = !inside; next } inside' "$root/$doc" |
    sed -e ':a' -e '/\\$/N; s/\\\n//; ta' |
    grep -E '^[[:space:]]*ecoterra ' |
    sed -e 's/[[:space:]]\{2,\}#.*$//' >"$dir/commands.txt"
  count=0
  while IFS= read -r cmd; do
    count=$((count + 1))
    start=$(date +%s%N)
    if ! (cd "$dir" && PATH="$build/apps/ecoterra:$PATH" bash -c "$cmd" >"$dir/out.txt" 2>&1 </dev/null); then
      echo "FAILED ($doc): $cmd"
      cat "$dir/out.txt"
      exit 1
    fi
    ms=$((($(date +%s%N) - start) / 1000000))
    printf '%5d.%01d s  %s: %s\n' $((ms / 1000)) $((ms % 1000 / 100)) "$doc" "$cmd"
  done <"$dir/commands.txt"
  [ "$count" -gt 10 ] || { echo "only $count commands found in $doc"; exit 1; }
  rm -rf "$dir"
done
