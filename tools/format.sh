#!/usr/bin/env bash
# Formats the C++ sources (*.cpp, *.h and the *.inc files included as C++) with clang-format
# (.clang-format), or checks them with --check (exit 1 and a list of files when any would
# change). Shaders are left as written: clang-format does not know GLSL's layout qualifiers.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
mapfile -t files < <(git ls-files '*.cpp' '*.h' '*.inc')
if [[ "${1:-}" == "--check" ]]; then
  clang-format --dry-run --Werror "${files[@]}"
  echo "format: ${#files[@]} files clean"
else
  clang-format -i "${files[@]}"
fi
