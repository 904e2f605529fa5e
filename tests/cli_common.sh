# Helpers shared by the end-to-end CLI tests; source it after `set -uo pipefail`.
# Provides $here, $root, $work (removed on exit), $failures and the checks below.
here="$(cd "$(dirname "${BASH_SOURCE[1]}")" && pwd)"
root="$(dirname "$here")"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
failures=0

fail() { echo "FAIL: $*" >&2; failures=$((failures + 1)); }
py() { PYTHONDONTWRITEBYTECODE=1 /usr/bin/python3 -c "$@"; }
json_field() { py "import json,sys; d=json.load(sys.stdin); print(d$1)"; }

expect_exit() {  # expect_exit CODE CMD...
  local want="$1"; shift
  "$@" >"$work/out" 2>"$work/err"
  local got=$?
  [ "$got" -eq "$want" ] || fail "'$*' exited $got, expected $want; stderr: $(cat "$work/err")"
}

# expect_input_error PATTERN CMD...: exit 2, one line on stderr matching PATTERN, nothing on stdout
expect_input_error() {
  local pattern="$1"; shift
  expect_exit 2 "$@"
  [ "$(wc -l <"$work/err")" -eq 1 ] || fail "'$*': error is not one line: $(cat "$work/err")"
  grep -q -- "$pattern" "$work/err" || fail "'$*': error lacks '$pattern': $(cat "$work/err")"
  [ ! -s "$work/out" ] || fail "'$*': printed on stdout despite failing"
}

# py_meshes CODE: python with tests/plyfile.py and tests/testmeshes.py importable.
py_meshes() { py "import sys; sys.path.insert(0, '$here'); import testmeshes
$1"; }

# make_evaluation_meshes ICRKIT DIR: DIR/sim/object.ply (a simulated CAD
# object), DIR/raw.ply (its noisy copy) and DIR/filtered.ply (an exact copy
# with every 97th vertex excluded), for evaluate/report runs.
make_evaluation_meshes() {
  "$1" simulate --object wooden_toy_2 --sensor kinect --views 1 --seed 1 -o "$2/sim" --quiet >/dev/null ||
    { echo "FAIL: simulate" >&2; exit 1; }
  py_meshes "testmeshes.write_evaluation_meshes('$2/sim/object.ply', '$2/raw.ply', '$2/filtered.ply')" ||
    { echo "FAIL: writing the test meshes" >&2; exit 1; }
}
