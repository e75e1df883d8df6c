#!/usr/bin/env bash
# Counts the instructions of `obvh_bench probe` under callgrind, only inside the timed passes
# (traceProbeRepeats), and prints the count. Arguments go to the probe, e.g.
#   tools/bench/callgrind_probe.sh --library embree --workload diffuse --repeat 1
# OBVH_CALLGRIND_OUT=FILE keeps callgrind's profile (for callgrind_annotate); by default it is
# dropped. OBVH_BENCH=PATH takes another build's obvh_bench.
# Why a stand-in library: obvh_bench links OpenImageIO, which loads Debian's libhwy (through
# libjxl). On some CPUs (seen on an AMD EPYC of family 26, Zen 5) libhwy's load-time constructor
# executes RDTSCP, which valgrind 3.19 cannot decode: the run dies with SIGILL before main. The
# probe never writes an image, so an empty libhwy.so.1 put first on the library path is enough.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bench="${OBVH_BENCH:-$root/build/tools/obvh_bench}"
if ! command -v valgrind > /dev/null; then
  echo "callgrind_probe: valgrind is not installed (apt-get install valgrind)" >&2
  exit 1
fi
if [ ! -x "$bench" ]; then
  echo "callgrind_probe: $bench not found: build first (tools/setup/build.sh) or set OBVH_BENCH" >&2
  exit 1
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
echo "" > "$work/empty.c"
cc -shared -fPIC -Wl,-soname,libhwy.so.1 -o "$work/libhwy.so.1" "$work/empty.c"
LD_LIBRARY_PATH="$work${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" \
  valgrind --tool=callgrind --toggle-collect='*traceProbeRepeats*' \
  --callgrind-out-file="${OBVH_CALLGRIND_OUT:-/dev/null}" "$bench" probe "$@" 2> "$work/log" || {
  cat "$work/log" >&2
  exit 1
}
grep -v -e '^==' -e 'no version information available' "$work/log" >&2 || true
collected="$(sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$work/log")"
echo "callgrind_probe: ${collected:-?} instructions in the timed passes"
