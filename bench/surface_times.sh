#!/bin/sh
# Seconds per run of `outlinefit surface` on the surface paper's three example clouds, for
# parameter correction and the cuckoo searches at the default budget (the paper's setting).
# Usage: bench/surface_times.sh [RUNS]   (default 3 seeds per example and method)
set -eu
runs=${1:-3}
root=$(cd "$(dirname "$0")/.." && pwd)
cargo build --release --quiet --manifest-path "$root/Cargo.toml"
bin="$root/target/release/outlinefit"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
printf '%-8s %-12s %10s %14s\n' example method "s/run" "mean Y"
for ex in I II III; do
  for method in correct cs ics; do
    total=0; ysum=0
    seed=1
    while [ "$seed" -le "$runs" ]; do
      "$bin" surface --example "$ex" --param "$method" --seed "$seed" -o "$tmp/fit" 2>/dev/null
      s=$(python3 -c "import json;d=json.load(open('$tmp/fit.json'));print(d['fit']['seconds'],d['fit']['error'])")
      total=$(python3 -c "print($total+${s% *})"); ysum=$(python3 -c "print($ysum+${s#* })")
      seed=$((seed + 1))
    done
    python3 -c "print('%-8s %-12s %10.3f %14.6e' % ('$ex', '$method', $total/$runs, $ysum/$runs))"
  done
done
