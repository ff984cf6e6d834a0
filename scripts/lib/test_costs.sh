# CTest starts tests in order of their cost (seconds they took before), slowest first, so
# both cores stay busy to the end instead of one long test running alone at the end. A fresh
# tree has no costs yet; tests/slow_tests.txt (CTest's own CostData format: name, runs,
# seconds) carries those of the tests over 3 s, from an ASan run (every test but the
# release tree's `sweep` and `packaging` ones, whose release figures it keeps). A slow test
# missing there starts last: web_console_browser did, alone on one core for a minute.
# Sourced by scripts/test.sh.

# seed_test_costs TREE: gives TREE the recorded costs unless it has its own.
seed_test_costs() {
  local data="$1/Testing/Temporary/CTestCostData.txt"
  [ -f "$data" ] && return 0
  mkdir -p "$(dirname "$data")"
  cp tests/slow_tests.txt "$data"
}

# save_test_costs TREE: rewrites tests/slow_tests.txt from TREE's measured costs (run it
# after an ASan run when tests were added or got slower); tests TREE lacks keep theirs.
save_test_costs() {
  # Only tests the tree ran (CTest keeps the costs of removed ones, and seeded ones).
  ctest --test-dir "$1" -N -LE "sweep|packaging" | sed -n 's/^ *Test *#[0-9]*: //p' > "$1/test-names.txt"
  awk 'FILENAME == ARGV[1] { exists[$0] = 1; next }
       FILENAME == ARGV[2] { if ($1 == "---") nextfile; if (NF == 3 && $3 > 3 && ($1 in exists)) cost[$1] = $3; next }
       !($1 in exists) { cost[$1] = $3 }
       END { for (name in cost) printf "%s 1 %.1f\n", name, cost[name] }' \
    "$1/test-names.txt" "$1/Testing/Temporary/CTestCostData.txt" tests/slow_tests.txt | sort -k3 -nr > "$1/slow_tests.txt"
  mv "$1/slow_tests.txt" tests/slow_tests.txt
  rm -f "$1/test-names.txt"
}
