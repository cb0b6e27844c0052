# tests/support/report.sh - the ok/FAIL/skip protocol of the shell tests,
# sourced by tests/run.sh, tests/packaging.sh and tools/wintest.sh: one
# line a check - "ok    name", "FAIL  name", "skip  name: why" - counted;
# report_end prints the counts ("N passed, N failed" alone on the last
# line, which make test and CI read) and fails when anything failed.
passed=0
failed=0
skipped=0
pass() { passed=$((passed + 1)); echo "ok    $1"; }
fail() { failed=$((failed + 1)); echo "FAIL  $1"; }
skip() { skipped=$((skipped + 1)); echo "skip  $1"; }
# Count the ok/FAIL/skip lines another script prints on stdin; other
# lines pass through.
report_lines() {
  local line
  while IFS= read -r line; do
    case $line in
      "ok    "*) pass "${line#ok    }" ;;
      "FAIL  "*) fail "${line#FAIL  }" ;;
      "skip  "*) skip "${line#skip  }" ;;
      *) echo "$line" ;;
    esac
  done
}
# report_end NOTE: NOTE says where the skip lines' reasons are.
report_end() {
  [ "$skipped" = 0 ] || echo "$skipped skipped ($1)"
  echo "$passed passed, $failed failed"
  [ "$failed" = 0 ]
}
