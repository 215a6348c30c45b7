#!/usr/bin/env bash
# The C++ sources follow .clang-format: lists every file clang-format would change (fix: make format).
# Usage: format_check.sh CLANG_FORMAT SOURCE_DIR
set -euo pipefail
clang_format=$1
cd "$2"
if ! command -v "$clang_format" >/dev/null; then
  echo "format: clang-format is not installed (Debian package clang-format; make test installs it)"
  exit 1
fi
mapfile -t files < <(find models engines scenarios harness reports cli input tests bench examples \
  -path '*/node_modules' -prune -o \( -name '*.cpp' -o -name '*.hpp' -o -name '*.h' \) -print 2>/dev/null | sort)
if [ "${#files[@]}" -lt 100 ]; then
  echo "format: found only ${#files[@]} C++ files under $(pwd): not the source tree"
  exit 1
fi
bad=()
for f in "${files[@]}"; do
  "$clang_format" --style=file --dry-run -Werror "$f" >/dev/null 2>&1 || bad+=("$f")
done
if [ "${#bad[@]}" -gt 0 ]; then
  echo "format: ${#bad[@]} of ${#files[@]} files differ from .clang-format (run: make format):"
  printf '  %s\n' "${bad[@]}"
  exit 1
fi
echo "format: ${#files[@]} files follow .clang-format"
