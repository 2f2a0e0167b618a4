#!/usr/bin/env bash
# Fails when clang-format (the repository's .clang-format) would change a C++ file of the
# repository: CI runs it before the tests (.ci/run). Fix with: clang-format -i FILE...
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
    mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.h')
else
    mapfile -t files < <(find . -path ./build -prune -o -path './build-*' -prune -o -path ./.tools -prune \
        -o \( -name '*.cpp' -o -name '*.hpp' -o -name '*.h' \) -print)
fi
if ! clang-format --dry-run --Werror "${files[@]}" 2>/tmp/check-format.$$; then
    grep -E "^[^ ].*: (error|warning)" /tmp/check-format.$$ | cut -d: -f1 | sort -u | sed 's/^/not formatted: /'
    rm -f /tmp/check-format.$$
    echo "check-format: run clang-format -i on the files above"
    exit 1
fi
rm -f /tmp/check-format.$$
echo "check-format: ${#files[@]} files formatted"
