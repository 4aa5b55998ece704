#!/bin/sh
# Interleaved A/B of one pass's GPU time: `fovea run --json` of each build in turn, then in reverse order, ROUNDS
# times (A B B A ...), printing every run's median ms of PASS and each build's minimum. The machine is shared and
# noisy: compare builds only within one run of this script.
#   tools/ab_pass.sh PASS ROUNDS "BINARY_A ARGS..." "BINARY_B ARGS..." [...]
# e.g. tools/ab_pass.sh shade 2 "old/fovea run --eye-size 720x800 --frames 4" \
#        "build/release/tools/fovea/fovea run --eye-size 720x800 --frames 4 --hmd none --set gi.enabled=off"
set -eu
pass=$1 rounds=$2
shift 2
one() { sh -c "$1 --json" 2>/dev/null | /usr/bin/python3 -c "import json,sys; j=json.load(sys.stdin); print([round(p['gpu_ms_median'],1) for p in j['passes'] if p['name']=='$pass'][0])"; }
n=$#
i=0
for cmd in "$@"; do i=$((i+1)); eval "runs_$i=''"; done
r=0
while [ $r -lt "$rounds" ]; do
  for order in fwd rev; do
    i=0
    if [ $order = fwd ]; then list=$(seq 1 $n); else list=$(seq $n -1 1); fi
    for k in $list; do
      eval "cmd=\${$k}"
      ms=$(one "$cmd")
      eval "runs_$k=\"\$runs_$k $ms\""
    done
  done
  r=$((r+1))
done
k=1
while [ $k -le $n ]; do
  eval "cmd=\${$k}; runs=\$runs_$k"
  min=$(echo $runs | tr ' ' '\n' | sort -n | head -1)
  echo "$pass: min $min ms; runs:$runs; $cmd"
  k=$((k+1))
done
