#!/usr/bin/env bash
# Folds the inputs of longer fuzz runs into the committed corpus
# tests/fuzz/corpus/<kind>/, minimised with libFuzzer's -merge=1: an input is
# kept when it adds coverage beyond the seeds write_fuzz_seeds writes (CI
# writes those itself, so they are not committed) and the inputs kept before
# it. Inputs named crash-* (ones that broke a reader) are always kept.
#
#   tests/fuzz/merge_corpus.sh <fuzz build dir> <mat|text|list|keypoints> <input dir>...
#
# It runs one fuzz target process; run it when no other fuzzer is running.
set -euo pipefail
if [ $# -lt 3 ]; then
  echo "usage: $0 <fuzz build dir> <mat|text|list|keypoints> <input dir>..." >&2
  exit 2
fi
build=$(cd "$1" && pwd)
kind=$2
shift 2
case $kind in
  mat) target=fuzz_mat_reader ;;
  text) target=fuzz_text_reader ;;
  list) target=fuzz_observation_list ;;
  keypoints) target=fuzz_keypoints ;;
  *) echo "$0: the kind must be mat, text, list or keypoints, not '$kind'" >&2; exit 2 ;;
esac
fuzz_dir=$(cd "$(dirname "$0")" && pwd)
corpus=$fuzz_dir/corpus/$kind
mkdir -p "$corpus"
work=$(mktemp -d "$build/merge.XXXXXX")
trap 'rm -rf "$work"' EXIT

LSAN_OPTIONS=suppressions=$fuzz_dir/lsan.supp \
  "$build/write_fuzz_seeds" "$work/seeds" >/dev/null
mkdir "$work/kept"
cp "$work/seeds/$kind"/* "$work/kept/"
find "$corpus" -maxdepth 1 -type f -name 'crash-*' -exec cp {} "$work/kept/" \;

ASAN_OPTIONS=allocator_may_return_null=0 \
LSAN_OPTIONS=suppressions=$fuzz_dir/lsan.supp TMPDIR=$work \
  "$build/$target" -merge=1 -max_len=4096 -timeout=20 -rss_limit_mb=1536 \
  "$work/kept" "$corpus" "$@" 2>"$work/merge.log" ||
  { tail -20 "$work/merge.log" >&2; exit 1; }

# The new corpus: what the merge kept, less the seeds.
for seed in "$work/seeds/$kind"/*; do rm -f "$work/kept/$(basename "$seed")"; done
find "$corpus" -maxdepth 1 -type f -delete
cp "$work/kept"/* "$corpus/"
echo "$corpus: $(find "$corpus" -type f | wc -l) files, $(cat "$corpus"/* | wc -c) bytes"
