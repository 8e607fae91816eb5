#!/usr/bin/env bash
# Runs the shipped nrsfm binary on every file of the fuzz corpus of one kind
# (tests/fuzz/corpus/<mat|text|list>/) as a user would, in a process limited
# to 512 MB of address space (ulimit -v 524288): each run must end with
# exit code 0, or with exit code 1 and exactly one stderr line
# "nrsfm reconstruct: error: …"; never a kill, an abort, a std::bad_alloc,
# a CHECK or a sanitizer report. Prints the slowest file.
#
#   fuzz_corpus_cli_check.sh <nrsfm binary> <corpus dir> <mat|text|list> <work dir>
set -u
if [ $# -ne 4 ]; then
  echo "usage: $0 <nrsfm binary> <corpus dir> <mat|text|list> <work dir>" >&2
  exit 2
fi
cli=$1
corpus=$2
kind=$3
work=$4
case $kind in
  mat) extension=.mat ;;
  text) extension=.txt ;;
  list) extension=.obs ;;
  *) echo "$0: the kind must be mat, text or list, not '$kind'" >&2; exit 2 ;;
esac
rm -rf "$work"
mkdir -p "$work"
input=$work/input$extension
count=0
failures=0
slowest=0
slowest_file=
for file in "$corpus/$kind"/*; do
  count=$((count + 1))
  cp "$file" "$input"
  rm -rf "$work/out"
  start=$(date +%s%N)
  (ulimit -v 524288 && exec "$cli" reconstruct --input "$input" --K 1 --output "$work/out" \
    --quiet) >"$work/stdout" 2>"$work/stderr"
  status=$?
  elapsed=$((($(date +%s%N) - start) / 1000000))
  if [ "$elapsed" -gt "$slowest" ]; then
    slowest=$elapsed
    slowest_file=$(basename "$file")
  fi
  lines=$(wc -l <"$work/stderr")
  crash=$(grep -E -c "bad_alloc|terminate|Sanitizer|runtime error|Check failed" "$work/stderr")
  if [ "$status" -eq 0 ] && [ "$crash" -eq 0 ]; then
    continue
  fi
  if [ "$status" -eq 1 ] && [ "$lines" -eq 1 ] && [ "$crash" -eq 0 ] &&
    grep -q "^nrsfm reconstruct: error: " "$work/stderr"; then
    continue
  fi
  failures=$((failures + 1))
  echo "$kind/$(basename "$file"): exit $status, $lines stderr line(s): $(head -c 400 "$work/stderr")"
done
echo "$kind: $count files, $failures failure(s); slowest $slowest ms ($slowest_file)"
[ "$failures" -eq 0 ]
