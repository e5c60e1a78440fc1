# Sourced by scripts/benchmark.sh, defects.sh and ablation.sh: their tables go into docs/results.md
# (DSM_RESULTS: another file; "-": none), each between the markers of its section
#   <!-- results:SECTION -->  ...  <!-- /results:SECTION -->
# under a line that says which script wrote it, when, at which commit and on which machine. The
# section `accuracy` also goes into the README's results table, between the same markers.
#
#   RESULTS_COLUMNS=(name ...)            the table's columns, set before this file is sourced
#   results_header                        prints the table's header
#   some_command | results_tee SECTION    prints what it reads and, at its end, writes the section
# A script called with --print-header prints its header and ends here (the format a test checks).
RESULTS_FILE="${DSM_RESULTS-docs/results.md}"

results_header() {
  local column line="|" rule="|"
  for column in "${RESULTS_COLUMNS[@]}"; do
    line+=" $column |"
    rule+="---|"
  done
  echo "$line"
  echo "$rule"
}
if [ "${1:-}" = --print-header ]; then
  results_header
  exit 0
fi
# The arguments as a shell would take them again (those with spaces quoted).
results_args() {
  local arg out=""
  for arg in "$@"; do
    if [[ "$arg" == *" "* ]]; then out+=" \"$arg\""; else out+=" $arg"; fi
  done
  echo "${out# }"
}

# The provenance line of a section written now by `$0 $RESULTS_ARGS`.
results_provenance() {
  local commit dirty="" cpu
  commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
  # Changes to the files these scripts write do not count.
  if [ -n "$(git status --porcelain --untracked-files=no -- . ':!docs/results.md' ':!README.md' 2>/dev/null)" ]; then
    dirty=" with uncommitted changes"
  fi
  cpu=$(awk -F': ' '/^model name/ { print $2; exit }' /proc/cpuinfo 2>/dev/null)
  echo "Written by \`scripts/$(basename "$0")${RESULTS_ARGS:+ $RESULTS_ARGS}\` on $(date -u '+%Y-%m-%d %H:%M') UTC at commit $commit$dirty, on ${cpu:-an unknown CPU} ($(nproc) cores)."
}

# Replaces (or appends) section $1 of file $2 with the contents of file $3.
results_replace() {
  local section=$1 file=$2 body=$3 tmp
  tmp=$(mktemp)
  if [ -f "$file" ] && grep -q "^<!-- results:$section -->$" "$file"; then
    awk -v begin="<!-- results:$section -->" -v end="<!-- /results:$section -->" -v body="$body" '
      $0 == begin { print; while ((getline line < body) > 0) print line; skip = 1; next }
      $0 == end { skip = 0 }
      !skip { print }' "$file" >"$tmp"
  else
    { [ -f "$file" ] && cat "$file"; echo; echo "<!-- results:$section -->"; cat "$body"; echo "<!-- /results:$section -->"; } >"$tmp"
  fi
  mv "$tmp" "$file"
}

results_tee() {
  local section=$1 table body
  table=$(mktemp)
  tee "$table"
  [ "$RESULTS_FILE" = "-" ] && { rm -f "$table"; return 0; }
  body=$(mktemp)
  { results_provenance; echo; cat "$table"; } >"$body"
  results_replace "$section" "$RESULTS_FILE" "$body"
  if [ "$section" = accuracy ] && [ -f README.md ] && grep -q "^<!-- results:accuracy -->$" README.md; then
    results_replace accuracy README.md "$body"
  fi
  rm -f "$table" "$body"
  echo "results: section '$section' written to $RESULTS_FILE" >&2
}
