# Named, timed stages for scripts that run long (sourced by scripts/test.sh). `stage NAME
# CMD...` runs CMD and records how long it took; when the script exits, however it exits,
# a table of every stage's time is printed with the failed stage marked.
stage_names=()
stage_seconds=()
stage_failed=""
stages_started=$SECONDS

stage() {
  local name=$1 start=$SECONDS
  shift
  printf '\n== %s ==\n' "$name"
  if "$@"; then
    stage_names+=("$name")
    stage_seconds+=($((SECONDS - start)))
  else
    local rc=$?
    stage_names+=("$name")
    stage_seconds+=($((SECONDS - start)))
    stage_failed=$name
    return "$rc"
  fi
}

print_stage_times() {
  local i
  printf '\n== stage times ==\n'
  for i in "${!stage_names[@]}"; do
    printf '%6d s  %s%s\n' "${stage_seconds[$i]}" "${stage_names[$i]}" \
      "$([ "${stage_names[$i]}" = "$stage_failed" ] && echo '  (FAILED)')"
  done
  printf '%6d s  total\n' $((SECONDS - stages_started))
  if command -v ccache > /dev/null; then
    ccache --print-stats 2> /dev/null | awk -F'\t' '$1=="direct_cache_hit"||$1=="preprocessed_cache_hit"{h+=$2} $1=="cache_miss"{m=$2}
      END{if (h+m>0) printf "ccache: %d hits, %d misses since its counters were last zeroed\n", h, m}'
  fi
}
trap print_stage_times EXIT
