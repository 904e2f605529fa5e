#!/usr/bin/env bash
# End-to-end: `icrkit report` on a small `icrkit evaluate` run folder. Checks
# the page is self-contained (nothing to fetch), lists missing files instead
# of failing, rejects a RUN_DIR that does not exist, and - where Debian's
# `chromium` is installed - opens it headless with networking off: the page
# must report its first frame with no errors, hold Table I and the viewer
# canvas, and the canvas must not be blank in a screenshot (saved to
# $ICRKIT_TEST_ARTEFACTS/report.png). Without chromium the browser checks are
# skipped (exit 77) after everything else passed.
set -uo pipefail
source "$(dirname "$0")/cli_common.sh"
icrkit="${ICRKIT:?set ICRKIT to the icrkit binary}"
artefacts="${ICRKIT_TEST_ARTEFACTS:-$work/artefacts}"

# CAD, raw (noisy copy) and filtered (exact copy with a few excluded vertices) meshes.
make_evaluation_meshes "$icrkit" "$work"

run="$work/run"
expect_exit 0 "$icrkit" evaluate --cad "$work/sim/object.ply" --raw "$work/raw.ply" --filtered "$work/filtered.ply" \
  --name toy --grasps 4 -o "$run" --quiet
[ -s "$run/grasps.jsonl" ] || { echo "FAIL: evaluate wrote no run folder: $(cat "$work/err")" >&2; exit 1; }
# A render of our own (evaluate may have written some too), so that the
# renders section has something to embed.
mkdir -p "$run/renders" && cp "$run/fig8_4fingers.png" "$run/renders/example.png"
pngs=$(find "$run/renders" -name '*.png' | wc -l)

report="$work/report.html"
expect_exit 0 "$icrkit" report "$run" -o "$report" --json
cp "$work/out" "$work/report.json"
py "
import json, re, sys
s = json.load(open('$work/report.json'))
assert s['missing'] == [], s['missing']
assert s['renders'] == $pngs, (s['renders'], $pngs)
v = s['viewer']
assert [m['mesh'] for m in v['meshes']] == ['cad', 'raw', 'filtered'], v
assert v['regions'] == any(json.loads(l)['evaluated'] for l in open('$run/grasps.jsonl')), v
html = open('$report', encoding='utf-8').read()
assert len(open('$report', 'rb').read()) == s['bytes']['total'], s['bytes']
for needle in ('id=\"table1\"', 'id=\"eligibility-table\"', 'id=\"report-status\"', 'data:image/png;base64,',
               'fig8_4fingers.svg', 'fig8_5fingers.svg', '<svg', 'id=\"planned-table\"', 'id=\"surface-table\"'):
    assert needle in html, 'report lacks ' + needle
if v['threejs']:
    assert '<canvas id=\"viewer\"' in html, 'no viewer canvas'
else:
    assert '3D viewer unavailable: three.js was not vendored at build time' in html
# Self-contained: no element that loads a URL, and http(s) only in XML namespace names (not fetched).
urls = [m for m in re.finditer(r'https?://[^\s\"\'<>)]*', html)]
bad = [m.group(0) for m in urls if not re.search(r'xmlns(:\w+)?=\"$', html[max(0, m.start() - 20):m.start()])]
assert not bad, 'network URLs in the report: %s' % bad[:5]
assert not re.search(r'<(script|img|iframe|embed|source|audio|video)\b[^>]*\ssrc=\"(?!data:)', html, re.I), 'external src'
assert not re.search(r'<link\b', html, re.I), 'a <link> element'
assert not re.search(r'@import|url\((?!data:)', html), 'CSS import or url()'
" || fail "report content or JSON summary"

# Another grasp; a cap on the faces; --grasp errors are usage errors.
first=$(py "import json; r=[json.loads(l) for l in open('$run/grasps.jsonl')]; print('%s/%d/%d' % (r[-1]['dataset'], r[-1]['fingers'], r[-1]['index']))")
expect_exit 0 "$icrkit" report "$run" -o "$work/other.html" --grasp "$first" --max-faces 2000 --json
py "
import json
s = json.load(open('$work/out'))
assert s['viewer']['grasp'] == '$first', s['viewer']
for m in s['viewer']['meshes']:
    assert m['faces'] <= 2000 and m['source_faces'] > 2000, m
" || fail "--grasp / --max-faces"
expect_input_error "no grasp toy/9/9" "$icrkit" report "$run" -o "$work/bad.html" --grasp toy/9/9
expect_input_error "DATASET/FINGERS/INDEX" "$icrkit" report "$run" -o "$work/bad.html" --grasp toy-4-0
[ ! -e "$work/bad.html" ] || fail "a failed report left bad.html behind"

# Bad input: missing files give a report that names them; no run folder is exit 2.
partial="$work/partial"
cp -r "$run" "$partial" && rm -rf "$partial/table1.json" "$partial/grasps.jsonl" "$partial/renders"
expect_exit 0 "$icrkit" report "$partial" -o "$work/partial.html" --json
py "
import json, re
s = json.load(open('$work/out'))
names = ' '.join(s['missing'])
assert 'table1.json' in names and 'grasps.jsonl' in names, s['missing']
html = open('$work/partial.html', encoding='utf-8').read()
section = re.search(r'<section id=\"missing\".*?</section>', html, re.S)
assert section and 'table1.json' in section.group(0) and 'grasps.jsonl' in section.group(0), 'no Missing section'
assert 'Table I unavailable' in html and 'No renders in this run folder' in html
" || fail "a run folder missing files did not give a report naming them"
expect_input_error "does not exist" "$icrkit" report "$work/no_such_run" -o "$work/bad.html"
touch "$work/a_file"
expect_input_error "not a directory" "$icrkit" report "$work/a_file" -o "$work/bad.html"

# The browser checks.
browser=""
for candidate in chromium chromium-browser; do
  if command -v "$candidate" >/dev/null 2>&1; then browser="$(command -v "$candidate")"; break; fi
done
if [ -z "$browser" ]; then
  [ "$failures" -eq 0 ] || exit 1
  echo "cli_report: chromium not installed; browser checks skipped (scripts/install-deps.sh installs it)" >&2
  exit 77
fi

# Headless with WebGL on SwiftShader (no GPU in CI), every host name
# unresolvable and a dead proxy: any fetch would fail (and the page's CSP
# would report it). Virtual time lets the viewer finish before the dump.
mkdir -p "$artefacts"
browse() {  # browse PAGE EXTRA-FLAGS...: runs chromium, stdout to $work/browser.out
  local page="$1"; shift
  timeout 180 "$browser" --headless=new --no-sandbox --disable-gpu --use-angle=swiftshader --enable-unsafe-swiftshader \
    --disable-dev-shm-usage --no-first-run --no-default-browser-check --user-data-dir="$work/chromium-profile" \
    --host-resolver-rules="MAP * ~NOTFOUND" --proxy-server="127.0.0.1:9" --proxy-bypass-list="<-loopback>" \
    --window-size=1280,2000 --virtual-time-budget=15000 "$@" "file://$page" >"$work/browser.out" 2>"$work/browser.err"
}
check_status() {  # check_status WANT-VIEWER: reads #report-status from the dumped DOM
  py "
import html, json, re, sys
dom = open('$work/browser.out', encoding='utf-8', errors='replace').read()
m = re.search(r'<pre id=\"report-status\">(.*?)</pre>', dom, re.S)
assert m, 'no #report-status in the DOM (did the page load?)'
status = json.loads(html.unescape(m.group(1)))
assert status.get('ready') is True, status
assert status.get('errors') == [], 'page errors: %s' % status.get('errors')
want = '$1'
assert status.get('viewer') == want, 'viewer is %s, expected %s' % (status.get('viewer'), want)
json.dump(status, open('$work/status.json', 'w'))
"
}

want_viewer=rendered
py "import json,sys; sys.exit(0 if json.load(open('$work/report.json'))['viewer']['threejs'] else 1)" || {
  want_viewer=unavailable
  echo "cli_report: NOTE: three.js was not vendored at build time; checking the 'viewer unavailable' message only" >&2
}
browse "$report" --dump-dom || fail "chromium --dump-dom exited $?: $(grep -v dbus "$work/browser.err" | tail -3)"
check_status "$want_viewer" || fail "the report's status after loading in chromium"
grep -q 'id="table1"' "$work/browser.out" || fail "no Table I in the rendered DOM"
if [ "$want_viewer" = rendered ]; then
  grep -q '<canvas id="viewer"' "$work/browser.out" || fail "no viewer canvas in the rendered DOM"
  browse "$report" --screenshot="$artefacts/report.png" || fail "chromium --screenshot exited $?"
  [ -s "$artefacts/report.png" ] || fail "no screenshot written"
  # Decode the PNG with the standard library (no PIL here) and measure the
  # pixel variance inside the canvas's rectangle, as the page reported it.
  py "
import json, struct, sys, zlib
status = json.load(open('$work/status.json'))
c = status['canvas']
data = open('$artefacts/report.png', 'rb').read()
assert data[:8] == b'\x89PNG\r\n\x1a\n', 'not a PNG'
pos, idat, header = 8, b'', None
while pos < len(data):
    length, kind = struct.unpack('>I4s', data[pos:pos + 8])
    chunk = data[pos + 8:pos + 8 + length]
    if kind == b'IHDR': header = struct.unpack('>IIBBBBB', chunk)
    elif kind == b'IDAT': idat += chunk
    pos += 12 + length
width, height, depth, colour, _, _, interlace = header
assert depth == 8 and colour in (2, 6) and interlace == 0, header
bpp = 3 if colour == 2 else 4
raw = zlib.decompress(idat)
stride = width * bpp
rows, prev, at = [], bytearray(stride), 0
for y in range(height):
    kind = raw[at]; line = bytearray(raw[at + 1:at + 1 + stride]); at += 1 + stride
    for i in range(stride):
        a = line[i - bpp] if i >= bpp else 0
        b = prev[i]; cc = prev[i - bpp] if i >= bpp else 0
        if kind == 1: line[i] = (line[i] + a) & 255
        elif kind == 2: line[i] = (line[i] + b) & 255
        elif kind == 3: line[i] = (line[i] + (a + b) // 2) & 255
        elif kind == 4:
            p = a + b - cc; pa, pb, pc = abs(p - a), abs(p - b), abs(p - cc)
            line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else cc)) & 255
    rows.append(line); prev = line
x0, y0 = c['x'] + 2, c['y'] + 2
x1, y1 = min(width, c['x'] + c['width'] - 2), min(height, c['y'] + c['height'] - 2)
assert x1 > x0 + 10 and y1 > y0 + 10, 'the canvas (%s) is not inside the %dx%d screenshot' % (c, width, height)
values = []
for y in range(y0, y1, 2):
    line = rows[y]
    for x in range(x0, x1, 2):
        values.append(0.299 * line[x * bpp] + 0.587 * line[x * bpp + 1] + 0.114 * line[x * bpp + 2])
mean = sum(values) / len(values)
variance = sum((v - mean) ** 2 for v in values) / len(values)
drawn = sum(1 for v in values if v < 245) / len(values)
print('cli_report: viewer canvas %dx%d at (%d, %d): luminance variance %.1f, %.1f %% non-white' %
      (c['width'], c['height'], c['x'], c['y'], variance, 100 * drawn), file=sys.stderr)
assert variance > 20 and drawn > 0.02, 'the viewer canvas looks blank'
" || fail "the viewer canvas is blank in the screenshot ($artefacts/report.png)"
fi

# The report of the incomplete run folder loads cleanly too.
browse "$work/partial.html" --dump-dom || fail "chromium --dump-dom (partial) exited $?"
check_status "$want_viewer" || fail "the partial report's status in chromium"
grep -q 'id="missing"' "$work/browser.out" || fail "no Missing section in the partial report's DOM"

[ "$failures" -eq 0 ] && echo "cli_report: all checks passed (screenshot: $artefacts/report.png)" >&2
exit $((failures > 0))
