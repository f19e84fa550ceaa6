#!/usr/bin/env bash
# Runs `principled bsdf chi2` over the whole issue-4 grid (256 Disney materials x 5 view angles)
# in parallel and reports failures. By default each run is tested at 0.01 with a Sidak
# correction over the 1280 runs (--tests 1280); pass TESTS=1 to test each run at 0.01 alone.
# Usage: docs/bsdf/chi2_grid.sh [path/to/principled] [jobs]
set -uo pipefail
BIN=${1:-build/bin/principled}
JOBS=${2:-2}
TESTS=${TESTS:-1280}
out=${KEEP:-$(mktemp)}  # KEEP=file keeps the per-run results
for r in 0.05 0.2 0.5 1; do
 for a in 0 0.8; do
  for m in 0 1; do
   for cc in "clearcoat=0" "clearcoat=1,clearcoatGloss=0" "clearcoat=1,clearcoatGloss=0.5" "clearcoat=1,clearcoatGloss=1"; do
    for s in 0 1; do
     for t in 0 0.7; do
      for th in 15 30 60 80 89; do
       echo "baseColor=0.8:0.6:0.4,roughness=$r,anisotropic=$a,metallic=$m,$cc,sheen=$s,specTrans=$t $th"
      done
     done
    done
   done
  done
 done
done | xargs -P "$JOBS" -L 1 sh -c '
  res=$("$0" bsdf chi2 --model disney --set "$1" --theta "$2" --tests '"$TESTS"' | tail -1)
  code=$?
  echo "$1 theta=$2 $res"' "$BIN" > "$out"
total=$(wc -l < "$out")
minp=$(awk '{print $NF}' "$out" | sort -g | head -1)
fails=$(awk -v n="$TESTS" 'BEGIN{a=1-(0.99)^(1/n)} {if ($NF < a) print}' "$out")
echo "runs $total, smallest p-value $minp"
echo "smallest five:"; awk '{print $NF, $0}' "$out" | sort -g | head -5 | cut -d' ' -f2-
[[ -z ${KEEP:-} ]] && rm -f "$out"
if [[ -n $fails ]]; then echo "failures:"; echo "$fails"; exit 1; fi
echo "all passed"
