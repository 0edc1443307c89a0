#!/usr/bin/env bash
# Formats every C++ source in place with the committed .clang-format.
set -euo pipefail
cd "$(dirname "$0")/.."
find common coordinator tracer-node client tools tests bench \( -name '*.h' -o -name '*.cpp' \) -print0 |
  xargs -0 -r clang-format -i --style=file
