#!/usr/bin/env bash
# Quick start, main job: set up, build, then trace the default scene with Debian's Embree and with
# obvh in one run, print the comparison and write both images to ./out; render it with obvh_render
# through each library and compare the two images.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
"$root/tools/setup/install_deps.sh"
"$root/tools/setup/build.sh"
mkdir -p "$root/out"
"$root/build/tools/obvh_bench" --out "$root/out" "$@"
# The same scene through the renderer, once per library, and the two images compared.
for library in embree obvh; do
  "$root/build/tools/obvh_render" /usr/share/glmark2/models/bunny.obj --library "$library" --quiet \
    -o "$root/out/render_bunny_$library.png"
done
"$root/build/tools/obvh_imgdiff" "$root/out/render_bunny_embree.png" "$root/out/render_bunny_obvh.png"
