#!/bin/sh
# Runs the request-parser fuzzer for a bounded time: run_fuzzer.sh CORPUS_DIR FUZZER SECONDS SEED_DIR.
# Inputs go up to the largest request the server accepts (socket.max_request_bytes is at most 1 MiB), and
# the corpus starts with a 100000-deep ?CONTROL argument (issue 23: its error message overflowed the stack).
set -eu
corpus=$1 fuzzer=$2 seconds=$3 seeds=$4
rm -rf "$corpus"
mkdir -p "$corpus"
{ printf '?CONTROL={"unpin":'; head -c 100000 /dev/zero | tr '\0' '['; } >"$corpus/deep_unpin"
{ printf '?WATCH={"x":'; head -c 100000 /dev/zero | tr '\0' '{' | sed 's/{/{"a":/g'; } >"$corpus/deep_watch"
exec "$fuzzer" -max_total_time="$seconds" -max_len=1048576 -timeout=10 -rss_limit_mb=4096 "$corpus" "$seeds"
