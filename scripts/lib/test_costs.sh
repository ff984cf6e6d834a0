# CTest starts tests in order of their cost (seconds they took before), slowest first, so
# both cores stay busy to the end instead of one long test running alone at the end. A fresh
# tree has no costs yet; tests/slow_tests.txt (CTest's own CostData format: name, runs,
# seconds) carries those of the tests over 3 s from a release run. Sourced by scripts/test.sh.

# seed_test_costs TREE: gives TREE the recorded costs unless it has its own.
seed_test_costs() {
  local data="$1/Testing/Temporary/CTestCostData.txt"
  [ -f "$data" ] && return 0
  mkdir -p "$(dirname "$data")"
  cp tests/slow_tests.txt "$data"
}

# save_test_costs TREE: rewrites tests/slow_tests.txt from TREE's measured costs (run it
# after a release run when tests were added or got slower).
save_test_costs() {
  # Only tests the tree still has (CTest keeps the costs of removed ones).
  ctest --test-dir "$1" -N | sed -n 's/^ *Test *#[0-9]*: //p' > "$1/test-names.txt"
  awk 'FNR == NR { exists[$0] = 1; next } $1 == "---" { exit }
       NF == 3 && $3 > 3 && ($1 in exists) { cost[$1] = $3 }
       END { for (name in cost) printf "%s 1 %.1f\n", name, cost[name] }' \
    "$1/test-names.txt" "$1/Testing/Temporary/CTestCostData.txt" | sort -k3 -nr > tests/slow_tests.txt
  rm -f "$1/test-names.txt"
}
