#!/usr/bin/env bash
# Quick start, tests: set up, build, rebuild the suites that run on obvh alone with
# AddressSanitizer + UndefinedBehaviorSanitizer and run them, then run every test suite.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
"$root/tools/setup/install_deps.sh"
"$root/tools/setup/build.sh"
"$root/tools/setup/fetch_render_assets.sh" > /dev/null

# Suites that load Debian's Embree next to obvh (dlopen with RTLD_DEEPBIND) cannot run under ASan.
echo "obvh: API, numerics and backend suites under ASan + UBSan"
cmake -S "$root" -B "$root/build-sanitize" -DCMAKE_BUILD_TYPE=Release -DOBVH_SANITIZE=ON > /dev/null
cmake --build "$root/build-sanitize" -j"$(nproc)" --target obvh_abi_test obvh_api_test obvh_numerics_test obvh_backend_test
ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --test-dir "$root/build-sanitize" --output-on-failure -j"$(nproc)" -L "api|numerics|backend" -LE crossval

echo "obvh: all suites"
ctest --test-dir "$root/build" --output-on-failure -j"$(nproc)" "$@"
