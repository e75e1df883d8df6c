#!/usr/bin/env bash
# Runs one of Debian's Embree tutorials (embree-tools) twice: on Debian's Embree and with obvh's
# drop-in libembree3.so.3 first on LD_LIBRARY_PATH. The program is not rebuilt: this is the
# "link in place of Embree" check.
#   run_tutorial.sh stdout OBVH_LIB_DIR WORK_DIR PROGRAM [ARGS...]
#       both runs must succeed and print the same output
#   run_tutorial.sh image  OBVH_LIB_DIR WORK_DIR IMGDIFF MAX_DIFFERING PROGRAM [ARGS...]
#       both runs must succeed; their images may differ in at most MAX_DIFFERING pixels
set -euo pipefail
mode=$1 obvh_lib=$2 work=$3
shift 3
mkdir -p "$work"
[ -e "$obvh_lib/libembree3.so.3" ] || { echo "no drop-in library in $obvh_lib" >&2; exit 1; }

on_embree() {  # on_embree LOG PROGRAM ARGS...
  local log=$1
  shift
  "$@" > "$log" 2>&1 || { echo "$1 failed on Debian's Embree:"; cat "$log"; exit 1; }
}

on_obvh() {  # on_obvh LOG PROGRAM ARGS...
  local log=$1
  shift
  # Captured first: with pipefail, grep -q closing the pipe early would make ldd fail with SIGPIPE.
  local resolved
  resolved=$(LD_LIBRARY_PATH="$obvh_lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" ldd "$(command -v "$1")")
  grep -q "$obvh_lib/libembree3.so.3" <<< "$resolved" || {
    echo "$1 does not resolve libembree3.so.3 to obvh's drop-in"; exit 1; }
  LD_LIBRARY_PATH="$obvh_lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" "$@" > "$log" 2>&1 || {
    echo "$1 failed on obvh:"; cat "$log"; exit 1; }
}

case "$mode" in
  stdout)
    program=$1
    on_embree "$work/$program.embree.log" "$@"
    on_obvh "$work/$program.obvh.log" "$@"
    diff -u "$work/$program.embree.log" "$work/$program.obvh.log"
    echo "$program: identical output on Embree and obvh:"
    cat "$work/$program.obvh.log"
    ;;
  image)
    imgdiff=$1 max_differing=$2 program=$3
    shift 2
    on_embree "$work/$program.embree.log" "$@" -o "$work/$program.embree.ppm"
    on_obvh "$work/$program.obvh.log" "$@" -o "$work/$program.obvh.ppm"
    "$imgdiff" "$work/$program.embree.ppm" "$work/$program.obvh.ppm" --max-differing "$max_differing"
    ;;
  *)
    echo "unknown mode $mode" >&2
    exit 2
    ;;
esac
