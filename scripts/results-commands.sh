#!/usr/bin/env bash
# The commands that reproduce the figures of docs/RESULTS.md (issue 13):
# every non-blank line of a ```sh block that is not a `#` comment.
#
#   scripts/results-commands.sh           list them (LINE<TAB>COMMAND)
#   scripts/results-commands.sh --run     run them all, in order (minutes to
#                                         hours; not for CI)
#   scripts/results-commands.sh --run N   run only the command on line N
#
# --run builds `limbfuse` (release) and puts it first on PATH, then runs each
# command in target/results-commands/work, a scratch directory where
# `../shared` points at the shared data beside the repository and `docs`
# at the repository's docs (so `docs/figures/...` outputs overwrite the
# committed figures: `git diff docs/figures` shows what changed). Each
# command's output goes to target/results-commands/logs/LINE.txt.
# `cargo test --workspace` checks, without running them, that every command
# is runnable (crates/limbfuse-studies/tests/integration/results_commands.rs,
# crates/limbfuse-cli/tests/integration/results_commands.rs), and that no figure is left
# without a committed command (the same limbfuse-studies test,
# issue_13_no_figure_without_a_committed_command: markers such as "not
# reproducible", "ad-hoc", "temporary", "reverted" fail it).
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
MD=${MD:-$ROOT/docs/RESULTS.md}

list() {
  awk '/^[[:space:]]*```/ { t = $0; gsub(/[[:space:]]/, "", t); insh = (!insh && t == "```sh"); next }
       insh && $0 !~ /^[[:space:]]*(#|$)/ { s = $0; sub(/^[[:space:]]+/, "", s); sub(/[[:space:]]+$/, "", s); print NR "\t" s }' "$MD"
}

case "${1:-}" in
  "" | --list)
    list
    ;;
  --run)
    only=${2:-}
    cargo build --release -q -p limbfuse-cli --manifest-path "$ROOT/Cargo.toml"
    export PATH="$ROOT/target/release:$PATH"
    R="$ROOT/target/results-commands"
    mkdir -p "$R/work" "$R/logs"
    ln -sfn "$(cd "$ROOT/.." && pwd)/shared" "$R/shared"
    ln -sfn "$ROOT/docs" "$R/work/docs"
    failed=0
    while IFS=$'\t' read -r line cmd; do
      if [ -n "$only" ] && [ "$line" != "$only" ]; then continue; fi
      echo "== docs/RESULTS.md:$line: $cmd"
      start=$(date +%s)
      if (cd "$R/work" && bash -c "$cmd") > "$R/logs/$line.txt" 2>&1; then
        echo "   ok ($(( $(date +%s) - start )) s, output in target/results-commands/logs/$line.txt)"
      else
        echo "   FAILED (output in target/results-commands/logs/$line.txt)"
        failed=$((failed + 1))
      fi
    done < <(list)
    if [ "$failed" -gt 0 ]; then
      echo "$failed command(s) failed"
      exit 1
    fi
    ;;
  *)
    echo "usage: $0 [--list | --run [LINE]]" >&2
    exit 2
    ;;
esac
