#!/usr/bin/env bash
# `slambooster summary RUN --get KEY`: the scripts' one reader of summary.json (issue 42). Known keys print,
# tab-separated; a key that is no field of the schema fails; a field this file lacks fails or prints --missing.
#   test_summary_get.sh SLAMBOOSTER SCRATCH_DIR
set -u
tool=$1 dir=$2
rm -rf "$dir" && mkdir -p "$dir"
fail() { echo "FAIL: $*"; exit 1; }
cat > "$dir/summary.json" <<'JSON'
{"schema_version": 1, "front_end": "run", "sequence": "/data/seq a", "controller": "adaptive", "frames": 12,
 "tracked": 11, "tracking_attempted": 12, "tracked_percent": 91.5, "computation_ms_per_frame": 7.25,
 "stage_ms_per_frame": {"track": 1.5}, "ate": {"rmse_m": 0.0418, "mean_m": 0.03, "max_m": 0.09,
 "median_m": 0.02, "unaligned_mean_m": 0.05, "matches": 12},
 "knobs": {"csr": 2, "icp": 1e-4, "pd": [8, 5, 4], "tr": 1, "ir": 3}}
JSON
got=$("$tool" summary "$dir" --get frames --get ate.rmse_m --get sequence --get stage_ms_per_frame.track) ||
  fail "known keys: exit $?"
[ "$got" = "$(printf '12\t0.0418\t/data/seq a\t1.5')" ] || fail "known keys printed '$got'"
# The initial knobs (an optional part: pipeline/knobs.h's Knobs) are fields of the schema.
got=$("$tool" summary "$dir" --get knobs.csr --get knobs.ir --get knobs.pd) || fail "the knobs: exit $?"
[ "$got" = "$(printf '2\t3\t[8,5,4]')" ] || fail "the knobs printed '$got'"
got=$("$tool" summary "$dir/summary.json" --get computation_ms_per_frame) || fail "the file's path: exit $?"
[ "$got" = 7.25 ] || fail "computation_ms_per_frame printed '$got'"
if out=$("$tool" summary "$dir" --get framez 2>&1); then fail "an unknown key passed: '$out'"; fi
echo "$out" | grep -q 'framez.*not a field' || fail "the unknown key's message: $out"
if out=$("$tool" summary "$dir" --get ate.rmse 2>&1); then fail "an unknown nested key passed: '$out'"; fi
if out=$("$tool" summary "$dir" --get moving_volume.shifts 2>&1); then fail "an absent field passed: '$out'"; fi
echo "$out" | grep -q 'has no' || fail "the absent field's message: $out"
got=$("$tool" summary "$dir" --missing - --get moving_volume.shifts --get energy.joules_per_frame --get frames) ||
  fail "--missing: exit $?"
[ "$got" = "$(printf -- '-\t-\t12')" ] || fail "--missing printed '$got'"
echo '{"schema_version": 1, "frames": "many"}' > "$dir/summary.json"
if out=$("$tool" summary "$dir" --get frames 2>&1); then fail "a mistyped field passed: '$out'"; fi
echo "$out" | grep -q '"frames"' || fail "the mistyped field's message: $out"
echo "ok"
