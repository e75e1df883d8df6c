#!/usr/bin/env bash
# Runs the embree_verify selection (embree_verify_selection.txt) with obvh's drop-in first on
# LD_LIBRARY_PATH, and with Debian's Embree for comparison; prints pass/fail/skip counts per
# selected group and in total. Fails when obvh fails a leaf, crashes, or skips more leaves than
# Embree on the same selection.
#   run_embree_verify.sh OBVH_LIB_DIR SELECTION_FILE WORK_DIR [PART/PARTS]
# PART/PARTS (e.g. 2/3) runs every PARTS-th selected group from the PART-th, so that several
# ctest entries can share the selection across cores.
set -uo pipefail
obvh_lib=$1 selection=$2 work=$3 part=${4:-1/1}
part_index=${part%/*} part_count=${part#*/}
mkdir -p "$work"
[ -e "$obvh_lib/libembree3.so.3" ] || { echo "no drop-in library in $obvh_lib"; exit 1; }
command -v embree_verify >/dev/null || { echo "embree_verify not found (install embree-tools)"; exit 1; }

# Whether Embree's AVX-512 target (AVX512F, CD, DQ, BW and VL) runs on this CPU: embree_verify
# registers its AVX512.* leaves only then, so a selected AVX512 group has nothing to run elsewhere.
cpu_has_avx512() {
  local flags
  flags=$(grep -m1 '^flags' /proc/cpuinfo 2>/dev/null)
  for flag in avx512f avx512cd avx512dq avx512bw avx512vl; do
    [[ " $flags " == *" $flag "* ]] || return 1
  done
}

# count FILE FIRST -> "passed failed skipped leaves" over the first FIRST leaf results (0: all)
count() {
  awk -v first="$2" '
    /\[PASSED\]|\[FAILED\]|SKIPPED/ {
      if (first > 0 && n >= first) next
      n++
      if ($0 ~ /\[PASSED\]/) p++; else if ($0 ~ /\[FAILED\]/) f++; else s++
    }
    END { printf "%d %d %d %d\n", p, f, s, n }' "$1"
}

status=0
total_o=(0 0 0) total_e=(0 0 0)
printf "%-48s %27s   %27s\n" "selected group" "obvh passed/failed/skipped" "embree passed/failed/skipped"
index=0
start_all=$(date +%s)
while read -r keyword regex rest; do
  [ "$keyword" = select ] || continue
  index=$((index + 1))
  [ $(( (index - 1) % part_count + 1 )) -eq "$part_index" ] || continue
  first=0 obvh_only=0
  for option in $rest; do
    case "$option" in
      first=*) first=${option#first=} ;;
      obvh-only) obvh_only=1 ;;
    esac
  done
  # Not a skip to hide: on a CPU with AVX-512 the group runs, and "no leaf ran" below fails it.
  if [[ "$regex" == AVX512* ]] && ! cpu_has_avx512; then
    printf "%-48s %27s   %27s\n" "$regex" "(no AVX-512 on this CPU)" "(not run)"
    continue
  fi
  out_o="$work/$index.obvh.txt" out_e="$work/$index.embree.txt"
  LD_LIBRARY_PATH="$obvh_lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" timeout 900 \
    embree_verify --run "$regex" --no-colors --flatten > "$out_o" 2>&1
  rc_o=$?
  read -r p_o f_o s_o n_o <<< "$(count "$out_o" "$first")"
  # A crash or time-out before every counted leaf reported is a failure.
  if [ "$rc_o" -ge 124 ] && { [ "$first" -eq 0 ] || [ "$n_o" -lt "$first" ]; }; then
    echo "obvh: embree_verify --run '$regex' ended with status $rc_o (crash or time-out):"
    tail -5 "$out_o"
    status=1
  fi
  if [ "$obvh_only" -eq 0 ]; then
    timeout 900 embree_verify --run "$regex" --no-colors --flatten > "$out_e" 2>&1
    read -r p_e f_e s_e n_e <<< "$(count "$out_e" "$first")"
    embree="$p_e/$f_e/$s_e"
    total_e=($((total_e[0] + p_e)) $((total_e[1] + f_e)) $((total_e[2] + s_e)))
    [ "$s_o" -gt "$s_e" ] && { echo "obvh skipped more leaves than Embree in $regex"; status=1; }
  else
    embree="(not run)"
  fi
  printf "%-48s %27s   %27s\n" "$regex${first:+ }$( [ "$first" -gt 0 ] && echo "first=$first")" "$p_o/$f_o/$s_o" "$embree"
  total_o=($((total_o[0] + p_o)) $((total_o[1] + f_o)) $((total_o[2] + s_o)))
  [ "$n_o" -eq 0 ] && { echo "no leaf ran for $regex"; status=1; }
  if [ "$f_o" -gt 0 ]; then
    echo "obvh failed leaves:"; grep "\[FAILED\]" "$out_o" | head -10
    status=1
  fi
done < "$selection"
printf "%-48s %27s   %27s\n" "total" "${total_o[0]}/${total_o[1]}/${total_o[2]}" "${total_e[0]}/${total_e[1]}/${total_e[2]}"
echo "excluded groups (see $selection):"
grep '^exclude' "$selection" | sed 's/^exclude /  /'
echo "embree_verify selection (part $part) finished in $(( $(date +%s) - start_all )) s"
exit $status
