#!/usr/bin/env bash
# Quick start, tests: set up, build, run every test suite.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
"$root/tools/setup/install_deps.sh"
"$root/tools/setup/build.sh"
ctest --test-dir "$root/build" --output-on-failure -j"$(nproc)" "$@"
