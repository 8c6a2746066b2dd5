#!/usr/bin/env bash
# facet compare-runs on records nobody checked: every field of the wrong type is an error naming
# the file, line and field (never an abort), nesting is bounded, names are printed escaped, and the
# verdicts say which run is better for throughputs (higher) and for times (lower).
#   usage: compare_runs_test.sh FACET WORKDIR
set -u
facet="$1" work="$2"
rm -rf "$work" && mkdir -p "$work" && cd "$work" || exit 1
failed=0
check() { if eval "$2"; then echo "ok: $1"; else echo "FAILED: $1"; failed=1; fi; }

good_render='{"width": 64, "height": 36, "shading": "gouraud", "path": "simd", "frame_seconds": {"median": 0.2, "min": 0.19, "max": 0.21, "count": 5}}'
echo "$good_render" > good.json
# Each malformed record, and the field its message must name.
while IFS='|' read -r name record field; do
  printf '%s\n' "$record" > "$name.json"
  out=$("$facet" compare-runs "$name.json" good.json 2>&1); rc=$?
  check "$name: refused naming $field (exit $rc: $out)" '[ $rc -eq 2 ] && [[ "$out" == *"$name.json"* ]] && [[ "$out" == *"$field"* ]]'
done <<'EOF'
path_number|{"results": [{"path": 5, "vertices_lit_per_s": 1}]}|results[0].path
spread_number|{"width": 64, "height": 36, "shading": "gouraud", "path": "simd", "frame_seconds": 3}|frame_seconds
median_string|{"width": 64, "height": 36, "shading": "gouraud", "path": "simd", "frame_seconds": {"median": "x"}}|frame_seconds.median
summary_string|{"summary": "yes", "frame_seconds": {"median": 1}}|summary
count_negative|{"summary": true, "frame_seconds": {"median": 1, "count": -2}}|frame_seconds.count
results_object|{"results": {"path": "simd"}}|results
benchmark_time|{"benchmarks": [{"name": "BM_x", "real_time": "fast"}]}|benchmarks[0].real_time
width_string|{"width": "wide", "height": 36, "frame_seconds": {"median": 1}}|width
context_array|{"context": [1], "summary": true, "frame_seconds": {"median": 1}}|context
EOF
# A line of a multi-line record: named with its line.
printf '%s\n%s\n' "$good_render" '{"summary": 1, "frame_seconds": {"median": 1}}' > lines.json
out=$("$facet" compare-runs lines.json good.json 2>&1); rc=$?
check "a bad line is named with its number (exit $rc: $out)" '[ $rc -eq 2 ] && [[ "$out" == *"lines.json:2"* ]] && [[ "$out" == *"summary"* ]]'

# Nesting: 100,000 and 1,000,000 levels of context, with and without --json.
python3 -c "
import sys
for n, name in ((100000, 'deep1.json'), (1000000, 'deep2.json')):
    open(name, 'w').write('{\"context\": ' + '[' * n + ']' * n + ', \"summary\": true, \"frame_seconds\": {\"median\": 1}}')
"
for args in "deep1.json good.json --json" "deep2.json good.json"; do
  out=$("$facet" compare-runs $args 2>&1); rc=$?
  check "deep nesting is refused ($args: exit $rc)" '[ $rc -eq 2 ] && [[ "$out" == *"nests deeper"* ]]'
done

# A name with a terminal escape and invalid UTF-8 is printed escaped, in text and in JSON.
printf '{"benchmarks": [{"name": "BM_\\u001b[31mred\\u0007", "real_time": 10}]}\n' > esc_a.json
printf '{"benchmarks": [{"name": "BM_\\u001b[31mred\\u0007", "real_time": 20}]}\n' > esc_b.json
out=$("$facet" compare-runs esc_a.json esc_b.json 2>&1); rc=$?
check "an escape in a name is escaped in text (exit $rc)" '[ $rc -eq 0 ] && ! printf "%s" "$out" | grep -q $'"'"'\x1b'"'"' && [[ "$out" == *"\\x1b[31mred"* ]]'
out=$("$facet" compare-runs esc_a.json esc_b.json --json 2>&1); rc=$?
check "and in JSON (exit $rc)" '[ $rc -eq 0 ] && ! printf "%s" "$out" | grep -q $'"'"'\x1b'"'"' && printf "%s" "$out" | python3 -c "import json,sys; json.load(sys.stdin)"'

# Verdicts: times are better lower, throughputs higher.
check "a slower benchmark is worse" '[[ "$out" == *"\"b_better\":false"* ]]'
echo '{"results": [{"path": "simd", "vertices_lit_per_s": 100}]}' > light_a.json
echo '{"results": [{"path": "simd", "vertices_lit_per_s": 200}]}' > light_b.json
out=$("$facet" compare-runs light_a.json light_b.json --json 2>&1); rc=$?
check "twice the vertices a second is better (exit $rc: $out)" '[ $rc -eq 0 ] && [[ "$out" == *"\"ratio\":2.0"* ]] && [[ "$out" == *"\"b_better\":true"* ]]'
out=$("$facet" compare-runs light_b.json light_a.json 2>&1); rc=$?
check "half the vertices a second is worse (exit $rc)" '[ $rc -eq 0 ] && [[ "$out" == *"B worse"* ]]'
sed 's/"median": 0.2, "min": 0.19, "max": 0.21/"median": 0.1, "min": 0.09, "max": 0.11/' good.json > faster.json
out=$("$facet" compare-runs good.json faster.json 2>&1); rc=$?
check "half the frame time is better, outside the spread (exit $rc: $out)" '[ $rc -eq 0 ] && [[ "$out" == *"B better"* ]] && [[ "$out" != *"within the spread"* ]]'
exit $failed
