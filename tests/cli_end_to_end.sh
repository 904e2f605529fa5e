#!/usr/bin/env bash
# End-to-end checks of the `icrkit` command: outputs, JSON, exit codes,
# error messages and atomic writes. Needs $ICRKIT (the binary); uses the
# shared real data when $ICRKIT_SHARED_DATA_DIR holds it.
set -uo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/cli_common.sh"

# --help everywhere
for cmd in "" info convert; do
  expect_exit 0 "$ICRKIT" $cmd --help
done
expect_exit 2 "$ICRKIT"
expect_exit 2 "$ICRKIT" frobnicate

# info on the bundled tetrahedron: known answers
tet="$root/datasets/tetrahedron.obj"
"$ICRKIT" info "$tet" --json >"$work/tet.json" 2>"$work/err" || fail "info on $tet failed: $(cat "$work/err")"
[ "$(json_field "['vertices']" <"$work/tet.json")" = 4 ] || fail "tetrahedron: expected 4 vertices"
[ "$(json_field "['faces']" <"$work/tet.json")" = 4 ] || fail "tetrahedron: expected 4 faces"
[ "$(json_field "['boundary_edges']" <"$work/tet.json")" = 0 ] || fail "tetrahedron: expected a closed mesh"
[ "$(json_field "['connected_components']" <"$work/tet.json")" = 1 ] || fail "tetrahedron: expected 1 component"
area=$(json_field "['area_m2']" <"$work/tet.json")
/usr/bin/python3 -c "import sys; sys.exit(0 if abs($area - 3**0.5) < 1e-12 else 1)" || fail "tetrahedron area $area, expected sqrt(3)"
# --json prints exactly one JSON object on stdout
[ "$(wc -l <"$work/tet.json")" -eq 1 ] || fail "--json printed more than one line"
# human output is key: value lines
"$ICRKIT" info "$tet" | grep -q "^vertices: 4$" || fail "human-readable info lacks 'vertices: 4'"

# convert round trips through every format keep the counts
for ext in ply obj; do
  expect_exit 0 "$ICRKIT" convert "$tet" "$work/t.$ext" --quiet
  "$ICRKIT" info "$work/t.$ext" --json >"$work/t.json" || fail "info on converted .$ext failed"
  [ "$(json_field "['faces']" <"$work/t.json")" = 4 ] || fail ".$ext lost faces"
done
expect_exit 0 "$ICRKIT" convert "$tet" "$work/t_ascii.ply" --ascii
head -c 200 "$work/t_ascii.ply" | grep -q "format ascii" || fail "--ascii did not write ASCII PLY"
for ext in pcd xyz; do
  "$ICRKIT" convert "$tet" "$work/t.$ext" --json >"$work/c.json" 2>/dev/null || fail "convert to .$ext failed"
  [ "$(json_field "['faces_dropped']" <"$work/c.json")" = 4 ] || fail "convert to .$ext: expected 4 dropped faces"
  "$ICRKIT" info "$work/t.$ext" --json >"$work/t.json" || fail "info on converted .$ext failed"
  [ "$(json_field "['vertices']" <"$work/t.json")" = 4 ] || fail ".$ext lost vertices"
done

# bad input: exit 2 and one line naming the file and the place
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n' >"$work/truncated.ply"
expect_exit 2 "$ICRKIT" info "$work/truncated.ply"
[ "$(wc -l <"$work/err")" -eq 1 ] || fail "error message is not one line: $(cat "$work/err")"
grep -q "truncated.ply" "$work/err" || fail "error does not name the file: $(cat "$work/err")"
grep -q "line" "$work/err" || fail "error does not name the line: $(cat "$work/err")"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n' >"$work/bad_index.obj"
expect_exit 2 "$ICRKIT" info "$work/bad_index.obj"
grep -q "line 4" "$work/err" || fail "OBJ index error does not name line 4: $(cat "$work/err")"
expect_exit 2 "$ICRKIT" info "$work/does_not_exist.ply"
expect_exit 2 "$ICRKIT" info "$work/t.stl"

# outputs are atomic: a failed conversion leaves nothing behind
expect_exit 2 "$ICRKIT" convert "$work/truncated.ply" "$work/never.ply"
[ ! -e "$work/never.ply" ] || fail "a failed conversion left an output file"
expect_exit 2 "$ICRKIT" convert "$tet" "$work/no/such/dir/out.ply"
[ -z "$(ls -A "$work" | grep '\.tmp\.')" ] || fail "a temporary file was left behind"

# the shared real data, when present
data="${ICRKIT_SHARED_DATA_DIR:-}"
if [ -n "$data" ] && [ -f "$data/stanford-bunny/bun_zipper.ply" ]; then
  "$ICRKIT" info "$data/stanford-bunny/bun_zipper.ply" --json >"$work/bunny.json" || fail "info on bun_zipper.ply failed"
  [ "$(json_field "['vertices']" <"$work/bunny.json")" = 35947 ] || fail "bun_zipper.ply: expected 35947 vertices"
  [ "$(json_field "['faces']" <"$work/bunny.json")" = 69451 ] || fail "bun_zipper.ply: expected 69451 faces"
  while IFS= read -r -d '' f; do
    "$ICRKIT" info "$f" --json --quiet >/dev/null 2>"$work/err" || fail "$f does not load: $(cat "$work/err")"
  done < <(find "$data" -type f \( -name '*.ply' -o -name '*.obj' -o -name '*.pcd' -o -name '*.xyz' \) -print0)
else
  echo "note: shared data not found at '${data}', real-data checks skipped" >&2
fi

if [ "$failures" -gt 0 ]; then
  echo "$failures check(s) failed" >&2
  exit 1
fi
echo "all CLI checks passed"
