#!/usr/bin/env bash
# Every `pfill ...` command the README shows in its indented examples runs as
# written (in order, in a scratch folder, with this build's pfill on PATH)
# and exits 0: the README's promises are tested, not just read.
set -u
readme="$(cd "$(dirname "$0")/.." && pwd)/README.md"
source "$(dirname "$0")/cli_test_lib.sh"
bin="$(mktemp -d)"
ln -s "$pfill" "$bin/pfill"
export PATH="$bin:$PATH"
ran=0
while IFS= read -r line; do
  command="${line#    }"
  ran=$((ran + 1))
  if ! bash -c "$command" > out.txt 2> err.txt; then
    fail "README: '$command' failed: $(tail -n 2 err.txt)"
  fi
done < <(grep -E '^    pfill (fill|render|info|check|devices) [^A-Z]*$' "$readme" | grep -v '\.\.\.')
rm -rf "$bin"
[ "$ran" -ge 8 ] || fail "found only $ran README commands to run"
if [ "$failures" -eq 0 ]; then echo "README commands: $ran run, all passed"; else exit 1; fi
