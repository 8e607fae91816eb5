#!/usr/bin/env bash
# Runs the shipped nrsfm binary on every file of the fuzz corpus of one kind
# (tests/fuzz/corpus/<mat|text|list|keypoints>/; a keypoints file as a COCO
# results file and, when it holds a form feed, split there as
# tests/fuzz/fuzz_keypoints.cc splits it, as the three files of an OpenPose
# folder) as a user would, in a
# process limited
# to 512 MB of address space (ulimit -v 524288): each run must end with
# exit code 0, or with exit code 1 and exactly one stderr line
# "nrsfm reconstruct: error: …"; never a kill, an abort, a std::bad_alloc,
# a CHECK or a sanitizer report. Prints the slowest file.
#
#   fuzz_corpus_cli_check.sh <nrsfm binary> <corpus dir> <mat|text|list|keypoints> <work dir>
set -u
if [ $# -ne 4 ]; then
  echo "usage: $0 <nrsfm binary> <corpus dir> <mat|text|list|keypoints> <work dir>" >&2
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
  keypoints) extension=.json ;;
  *) echo "$0: the kind must be mat, text, list or keypoints, not '$kind'" >&2; exit 2 ;;
esac
rm -rf "$work"
mkdir -p "$work"
input=$work/input$extension
count=0
failures=0
slowest=0
slowest_file=
# One run of the binary on $1 (a file or a folder); a failure is counted and
# printed with the corpus file's name $2.
run_one() {
  rm -rf "$work/out"
  start=$(date +%s%N)
  (ulimit -v 524288 && exec "$cli" reconstruct --input "$1" --K 1 --output "$work/out" \
    --quiet) >"$work/stdout" 2>"$work/stderr"
  status=$?
  elapsed=$((($(date +%s%N) - start) / 1000000))
  if [ "$elapsed" -gt "$slowest" ]; then
    slowest=$elapsed
    slowest_file=$2
  fi
  lines=$(wc -l <"$work/stderr")
  crash=$(grep -E -c "bad_alloc|terminate|Sanitizer|runtime error|Check failed" "$work/stderr")
  if [ "$status" -eq 0 ] && [ "$crash" -eq 0 ]; then
    return
  fi
  if [ "$status" -eq 1 ] && [ "$lines" -eq 1 ] && [ "$crash" -eq 0 ] &&
    grep -q "^nrsfm reconstruct: error: " "$work/stderr"; then
    return
  fi
  failures=$((failures + 1))
  echo "$kind/$2: exit $status, $lines stderr line(s): $(head -c 400 "$work/stderr")"
}
for file in "$corpus/$kind"/*; do
  count=$((count + 1))
  cp "$file" "$input"
  run_one "$input" "$(basename "$file")"
  if [ "$kind" = keypoints ] && grep -q $'\f' "$file"; then
    # The OpenPose folder: the parts between form feeds, in this order (a
    # file without one is a folder of one file much like the COCO run).
    rm -rf "$work/openpose"
    mkdir -p "$work/openpose"
    perl -e 'local $/; my @parts = split(/\f/, <STDIN>, 4);
      my @names = ("f_1_keypoints.json", "f_2_keypoints.json", "f_10_keypoints.json");
      for my $i (0 .. 2) {
        open(my $out, ">", "$ARGV[0]/$names[$i]") or die;
        binmode $out; print $out (defined $parts[$i] ? $parts[$i] : "");
      }' "$work/openpose" <"$file"
    run_one "$work/openpose" "$(basename "$file") (OpenPose folder)"
  fi
done
echo "$kind: $count files, $failures failure(s); slowest $slowest ms ($slowest_file)"
[ "$failures" -eq 0 ]
