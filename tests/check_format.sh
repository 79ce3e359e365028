#!/bin/sh
# tests/check_format.sh SOURCE_DIR: the `format` ctest. Every tracked C/C++ file follows .clang-format
# (the SDK's templates excepted: CMake configure_file inputs). Prints the files that do not, and how
# to fix them.
set -u
cd "$1" || exit 1
files=$(git ls-files '*.cpp' '*.hpp' '*.h' '*.c' ':!sdk/templates') || { echo "format: not a git checkout: $1"; exit 1; }
bad=$(echo "$files" | xargs clang-format --dry-run 2>&1 | grep -o '^[^:]*:[0-9]*:[0-9]*: warning' | cut -d: -f1 | sort -u)
if [ -n "$bad" ]; then
  echo "format: these files do not follow .clang-format:"
  echo "$bad"
  echo "fix: clang-format -i FILE (or: git ls-files '*.cpp' '*.hpp' '*.h' '*.c' ':!sdk/templates' | xargs clang-format -i)"
  exit 1
fi
echo "format: $(echo "$files" | wc -l) files follow .clang-format"
