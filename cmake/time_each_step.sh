#!/bin/bash
# A compiler / linker launcher that logs the CPU time (user, sys) and wall
# time of each compile or link to $NRSFM_TIME_LOG (docs/ci.md):
#   cmake -S . -B build -DCMAKE_CXX_COMPILER_LAUNCHER=$PWD/cmake/time_each_step.sh \
#         -DCMAKE_CXX_LINKER_LAUNCHER=$PWD/cmake/time_each_step.sh
#   NRSFM_TIME_LOG=/tmp/steps.log cmake --build build -j2
#   sort -rn /tmp/steps.log | head   # user sys wall output
out=""
prev=""
for arg in "$@"; do
  if [ "$prev" = "-o" ]; then out=$arg; fi
  prev=$arg
done
exec /usr/bin/time -a -o "${NRSFM_TIME_LOG:-/tmp/nrsfm_time_each_step.log}" \
  -f "%U %S %e $out" "$@"
