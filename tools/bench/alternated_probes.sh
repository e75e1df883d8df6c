#!/usr/bin/env bash
# Compares two libraries on one probe workload by alternating them: `obvh_bench probe` with library
# A, then with B, N times over, each run pinned to one CPU. Prints each alternation's best passes
# and its ratio B / A, then the median of those ratios and the ratio of the best passes overall:
#   tools/bench/alternated_probes.sh [--alternations N] [--cpu C] [--scene FILE] [--repeat R]
#                                    --workload W A B
# A and B are what `obvh_bench probe --library` takes: obvh, embree or the path of another build's
# libembree3.so.3 (e.g. `embree obvh` gives obvh's speed over Embree's). Defaults: 3 alternations,
# the last CPU, 20 passes a run, the probe's default scene (the bunny).
# OBVH_BENCH=PATH takes another build's obvh_bench.
# Why alternate and pin: on shared virtual machines a run often goes 10-25% slow for reasons outside
# the process; two runs back to back share most such spells, and pinning keeps the scheduler from
# moving the thread between the cores mid-pass. Read the median ratio; the best-pass ratio is the
# least disturbed one.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bench="${OBVH_BENCH:-$root/build/tools/obvh_bench}"
alternations=3 cpu=$(($(nproc) - 1)) repeat=20 workload="" scene=()
usage() {  # usage [EXIT_CODE]
  sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//' >&2
  exit "${1:-2}"
}
libraries=()
while [ $# -gt 0 ]; do
  case "$1" in
    --alternations) alternations="${2:?}"; shift 2 ;;
    --cpu) cpu="${2:?}"; shift 2 ;;
    --repeat) repeat="${2:?}"; shift 2 ;;
    --workload) workload="${2:?}"; shift 2 ;;
    --scene) scene=(--scene "${2:?}"); shift 2 ;;
    -h|--help) usage 0 ;;
    -*) echo "alternated_probes: unknown option $1" >&2; usage ;;
    *) libraries+=("$1"); shift ;;
  esac
done
[ -n "$workload" ] && [ ${#libraries[@]} -eq 2 ] || usage
if ! [[ "$alternations" =~ ^[1-9][0-9]*$ && "$repeat" =~ ^[1-9][0-9]*$ && "$cpu" =~ ^[0-9]+$ ]]; then
  echo "alternated_probes: --alternations and --repeat take positive integers, --cpu a CPU number" >&2
  exit 2
fi
if [ ! -x "$bench" ]; then
  echo "alternated_probes: $bench not found: build first (tools/setup/build.sh) or set OBVH_BENCH" >&2
  exit 1
fi
if ! taskset -c "$cpu" true 2> /dev/null; then
  echo "alternated_probes: cannot pin to CPU $cpu (this machine has $(nproc))" >&2
  exit 1
fi

# One probe run; prints its best pass in Mrays/s, or the probe's own error and fails.
best_pass() {
  local out
  if ! out="$(taskset -c "$cpu" "$bench" probe --library "$1" --workload "$workload" --repeat "$repeat" \
      "${scene[@]}" 2>&1)"; then
    echo "alternated_probes: the probe with --library $1 failed:" >&2
    echo "$out" >&2
    return 1
  fi
  local speed
  speed="$(sed -n 's/.*best of [0-9]* passes \([0-9.]*\) Mrays\/s.*/\1/p' <<< "$out" | tail -n 1)"
  if [ -z "$speed" ]; then
    echo "alternated_probes: no speed in the probe's output with --library $1:" >&2
    echo "$out" >&2
    return 1
  fi
  echo "$speed"
}

a_runs=() b_runs=()
for ((k = 1; k <= alternations; ++k)); do
  a="$(best_pass "${libraries[0]}")"
  b="$(best_pass "${libraries[1]}")"
  a_runs+=("$a") b_runs+=("$b")
  awk -v k="$k" -v a="$a" -v b="$b" 'BEGIN { printf "alternation %d: A %s, B %s Mrays/s, B/A %.3f\n", k, a, b, b / a }'
done
awk -v a="${a_runs[*]}" -v b="${b_runs[*]}" -v w="$workload" 'BEGIN {
  n = split(a, as, " "); split(b, bs, " ");
  bestA = 0; bestB = 0;
  for (i = 1; i <= n; ++i) {
    r[i] = bs[i] / as[i];
    if (as[i] > bestA) bestA = as[i];
    if (bs[i] > bestB) bestB = bs[i];
  }
  for (i = 2; i <= n; ++i) for (j = i; j > 1 && r[j - 1] > r[j]; --j) { t = r[j]; r[j] = r[j - 1]; r[j - 1] = t }
  median = n % 2 ? r[(n + 1) / 2] : (r[n / 2] + r[n / 2 + 1]) / 2;
  printf "%s: median B/A %.3f over %d alternations; best passes A %.2f, B %.2f Mrays/s, B/A %.3f\n",
         w, median, n, bestA, bestB, bestB / bestA
}'
