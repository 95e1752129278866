# Shared by the cli_*.sh tests (sourced): $pfill from the first argument, a
# scratch folder as the working directory (removed on exit), and fail(),
# which counts failures for the script's last line to report.
pfill="$1"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
