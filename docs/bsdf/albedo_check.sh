#!/usr/bin/env bash
# Reproduces every row of the reference albedo tables (reference/bsdf.md §4.3) with
# `principled bsdf albedo` and prints the largest deviation; exits 1 above 0.015.
# Usage: docs/bsdf/albedo_check.sh [path/to/principled]
set -euo pipefail
BIN=${1:-build/bin/principled}
worst=0
check() {  # model set lobes mu reference
  local model=$1 set=$2 lobes=$3 mu=$4 ref=$5 args=()
  [[ -n $set ]] && args+=(--set "$set")
  [[ -n $lobes ]] && args+=(--lobes "$lobes")
  local got
  got=$("$BIN" bsdf albedo --model "$model" "${args[@]}" --cos "$mu" --samples 1000000 | tail -1 | awk '{print $2}')
  local d
  d=$(awk -v a="$got" -v b="$ref" 'BEGIN{d=a-b; if(d<0)d=-d; printf "%.4f", d}')
  printf '%-6s %-44s %-8s mu=%-5s ref=%-6s got=%-8s diff=%s\n' "$model" "$set" "$lobes" "$mu" "$ref" "$got" "$d"
  worst=$(awk -v a="$d" -v b="$worst" 'BEGIN{print (a>b)?a:b}')
}
# Full Disney (white baseColor, separable G), mu = 1 .5 .2 .05
row() { local set=$1; shift; local mus=(1 0.5 0.2 0.05); for i in 0 1 2 3; do check disney "$set" "" "${mus[$i]}" "$1"; shift; done; }
row "roughness=0.2" 1.028 1.051 1.222 1.305
row "roughness=0.5" 1.043 1.064 1.148 1.189
row "roughness=1" 1.048 1.076 1.274 1.503
row "specular=1,roughness=0.5" 1.079 1.097 1.178 1.218
row "metallic=1,roughness=0.2" 0.998 0.995 0.975 0.884
row "metallic=1,roughness=0.5" 0.916 0.855 0.832 0.875
row "metallic=1,roughness=1" 0.307 0.409 0.511 0.584
row "roughness=0.5,sheen=1" 1.043 1.079 1.196 1.266
row "roughness=0.5,clearcoat=1,clearcoatGloss=1" 1.052 1.079 1.192 1.220
# Burley diffuse alone, mu = 1 .7 .5 .3 .1 .02
drow() { local r=$1; shift; local mus=(1 0.7 0.5 0.3 0.1 0.02); for i in 0 1 2 3 4 5; do check disney "roughness=$r" diffuse "${mus[$i]}" "$1"; shift; done; }
drow 0 0.976 0.975 0.961 0.894 0.688 0.535
drow 0.5 1.006 1.005 1.008 1.020 1.023 1.011
drow 1 1.036 1.035 1.057 1.151 1.380 1.518
# GGX alone, F = 1 (white metal), separable G, mu = 1 .5 .1
grow() { local model=$1 r=$2; shift 2; local mus=(1 0.5 0.1); for i in 0 1 2; do check "$model" "metallic=1,roughness=$r" "" "${mus[$i]}" "$1"; shift; done; }
grow disney 0.1 1.000 1.000 0.994
grow disney 0.25 0.996 0.988 0.892
grow disney 0.5 0.916 0.855 0.855
grow disney 0.75 0.627 0.647 0.746
grow disney 1 0.307 0.409 0.558
# UE4 specular with analytic k, F = 1, mu = 1 .5 .1
grow ue4 0.1 1.000 0.754 0.183
grow ue4 0.25 0.988 0.691 0.196
grow ue4 0.5 0.860 0.585 0.360
grow ue4 1 0.307 0.409 0.558
echo "max diff $worst"
awk -v w="$worst" 'BEGIN{exit (w>0.015)?1:0}'
