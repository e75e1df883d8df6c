#!/usr/bin/env bash
# Puts the renderer's real test asset into data/webxr/ (not committed): the Magic Leap 2
# controller from the npm package @webxr-input-profiles/assets (transmission, IOR, alpha BLEND,
# textures). The broken glTF samples come from Debian's assimp-testmodels (a listed package).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
data="${OBVH_DATA:-$root/data}"
target="$data/webxr/magicleap-two.glb"
mkdir -p "$data/webxr"
if [ ! -f "$target" ]; then
  if ! command -v npm > /dev/null; then
    sudo=""
    [ "$(id -u)" -ne 0 ] && sudo="sudo"
    echo "obvh assets: installing npm"
    $sudo apt-get update
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y --no-install-recommends npm
  fi
  work="$(mktemp -d)"
  (cd "$work" && npm pack --silent @webxr-input-profiles/assets@1.0.20 > /dev/null &&
     tar xzf webxr-input-profiles-assets-1.0.20.tgz package/dist/profiles/magicleap-two/none.glb)
  mv "$work/package/dist/profiles/magicleap-two/none.glb" "$target"
  rm -rf "$work"
fi
echo "$target"
