#!/usr/bin/env bash
# Quick start, main job: set up, build, then trace the default scene with Debian's Embree and with
# obvh in one run, print the comparison and write both images to ./out.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
"$root/tools/setup/install_deps.sh"
"$root/tools/setup/build.sh"
mkdir -p "$root/out"
"$root/build/tools/obvh_bench" --out "$root/out" "$@"
