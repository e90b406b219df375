#!/usr/bin/env bash
# The papers' failure claims (tests/it/stability*.rs, transparency_claims.rs) measured through the CLI under each
# light fit: `per-frame`, the fit the tests run under (tests/it/common's MEASURED_FIT), and `stable`, the shipped
# default. Each claim runs the `hairlab measure` commands its test's `run` helper runs (same preset, overrides,
# configurations, one frame), once per fit, and prints the figures the test compares, their ratio, the test's
# threshold and whether the claim holds by it. The claims the CLI cannot reach (the DSM vertex counts, FOM's
# unclamped ringing, MSM's bound through the GPU lookup, TC-4/5's deep pixels) are not here: docs/design.md says
# how they were measured.
#
#   scripts/claims-under-fits.sh [OUT]        # OUT (default claims-out) gets FIT/CLAIM/ folders and summary.txt
#
# Environment: HAIRLAB (default target/release/hairlab), FITS (default "per-frame stable"), CLAIMS (a subset of
# the claim names below, space-separated; default all). Needs bash, jq and awk. Exits 0 whatever the claims do.
set -euo pipefail

HAIRLAB=${HAIRLAB:-target/release/hairlab}
OUT=${1:-claims-out}
FITS=${FITS:-per-frame stable}
ALL="straight-grazing stray-strands mixed-sizes many-clumps one-stray-strand adsm avsm-stray avsm-default \
msm-six-moments fom-gpu tc1"
CLAIMS=${CLAIMS:-$ALL}
mkdir -p "$OUT"
SUMMARY=$OUT/summary.txt
: >"$SUMMARY"

say() { echo "$*" | tee -a "$SUMMARY"; }

# shadows DIR PRESET [--set K=V]... -- CONFIG...: `measure shadows` under $FIT into $OUT/$FIT/DIR.
shadows() {
  local dir=$OUT/$FIT/$1 preset=$2
  shift 2
  local args=()
  while [[ $1 != -- ]]; do
    args+=("$1")
    shift
  done
  shift
  for c in "$@"; do args+=(--config "$c"); done
  "$HAIRLAB" measure shadows --preset "$preset" --frames 1 --set "light.fit=$FIT" "${args[@]}" --out "$dir" \
    >"$dir.log" 2>&1 || { echo "failed: see $dir.log" >&2; exit 1; }
}

# v DIR ROW FIELD: a field of the ROW-th configuration (0-based, in the order given) of a `measure shadows` run.
v() { jq -r ".rows[$2][\"$3\"]" "$OUT/$FIT/$1/results.json"; }

# num EXPR: an awk expression's value, 4 significant digits.
num() { awk "BEGIN { printf \"%.4g\", $1 }"; }

# max A B: the larger, every digit kept.
max() { awk "BEGIN { printf \"%.17g\", ($1 > $2) ? $1 : $2 }"; }

# check TEXT CONDITION: one compared figure; CONDITION an awk expression, true when the claim holds.
check() {
  local verdict
  verdict=$(awk "BEGIN { print ($2) ? \"holds\" : \"FAILS\" }")
  say "  [$FIT] $1: $verdict"
  CHECKS=$((CHECKS + 1))
  [[ $verdict == holds ]] || FAILED=$((FAILED + 1))
}

claim_straight_grazing() {
  # stability::straight_grazing_bands_opacity_maps_but_not_deep_opacity_maps (Yuksel & Keyser Fig. 1)
  shadows straight-grazing straight-grazing -- osm:slices=16 osm:slices=64 osm:slices=256 dom:layers=3
  local o16 o64 o256 d3
  o16=$(v straight-grazing 0 map_error) o64=$(v straight-grazing 1 map_error)
  o256=$(v straight-grazing 2 map_error) d3=$(v straight-grazing 3 map_error)
  check "map error OSM-16 $(num "$o16") / DOM-3 $(num "$d3") = $(num "$o16/$d3") (> 1.5)" "$o16 > 1.5 * $d3"
  check "map error OSM-16/64 $(num "$o16/$o64"), OSM-64/256 $(num "$o64/$o256") (both > 1.2)" \
    "$o16 > 1.2 * $o64 && $o64 > 1.2 * $o256"
}

claim_stray_strands() {
  # stability::stray_strands_break_deep_opacity_maps_not_occupancy_maps (Sintorn & Assarsson Fig. 4/5a)
  shadows stray-64 stray-strand --set scene.generator.clumps=64 -- dom:layers=3 dom:layers=4 occupancy
  shadows stray-1 stray-strand --set scene.generator.clumps=1 -- dom:layers=3 dom:layers=4 occupancy
  local s3 s4 so m3 m4 mo s3one soone
  s3=$(v stray-64 0 shading_error) s4=$(v stray-64 1 shading_error) so=$(v stray-64 2 shading_error)
  m3=$(v stray-64 0 map_error) m4=$(v stray-64 1 map_error) mo=$(v stray-64 2 map_error)
  s3one=$(v stray-1 0 shading_error) soone=$(v stray-1 2 shading_error)
  check "shading DOM-3 $(num "$s3") / occupancy $(num "$so") = $(num "$s3/$so") (> 1.9)" "$s3 > 1.9 * $so"
  check "shading DOM-4 $(num "$s4") / occupancy = $(num "$s4/$so") (> 1.8)" "$s4 > 1.8 * $so"
  check "map error DOM-3 $(num "$m3/$mo")x, DOM-4 $(num "$m4/$mo")x occupancy $(num "$mo") (both > 4)" \
    "$m3 > 4 * $mo && $m4 > 4 * $mo"
  check "shading DOM-3 64 clumps / 1 clump $(num "$s3") / $(num "$s3one") = $(num "$s3/$s3one") (> 1.2)" \
    "$s3 > 1.2 * $s3one"
  check "shading occupancy 64 / 1 clump = $(num "$so/$soone") (in 0.95..1.05)" \
    "$so / $soone >= 0.95 && $so / $soone < 1.05"
}

claim_mixed_sizes() {
  # stability::mixed_sizes_favour_bounding_over_deep_opacity_maps (Voicu §4.1/5.5)
  shadows mixed-sizes mixed-sizes -- dom:layers=3 bom:layers=3 dom:layers=4 bom:layers=4 dom:layers=8 bom:layers=8
  local k i dm bm ds bs
  for i in 0 1 2; do
    k=$(jq -r ".rows[$((2 * i))].params.layers" "$OUT/$FIT/mixed-sizes/results.json")
    dm=$(v mixed-sizes $((2 * i)) map_error) bm=$(v mixed-sizes $((2 * i + 1)) map_error)
    ds=$(v mixed-sizes $((2 * i)) shading_error) bs=$(v mixed-sizes $((2 * i + 1)) shading_error)
    check "K=$k BOM/DOM map error $(num "$bm") / $(num "$dm") = $(num "$bm/$dm") (< 0.75)" "$bm < 0.75 * $dm"
    check "K=$k BOM/DOM shading $(num "$bs") / $(num "$ds") = $(num "$bs/$ds") (< 0.6)" "$bs < 0.6 * $ds"
  done
}

claim_many_clumps() {
  # stability::more_clumps_than_clusters_break_density_clustering (Mertens et al. Fig. 5)
  local q
  for q in 2 4 8; do shadows "many-clumps-$q" many-clumps --set "scene.generator.clumps=$q" -- dc:clusters=4; done
  local m2 m4 m8 w2 w4 w8 few fw
  m2=$(v many-clumps-2 0 map_error) m4=$(v many-clumps-4 0 map_error) m8=$(v many-clumps-8 0 map_error)
  w2=$(v many-clumps-2 0 worst_texel_error) w4=$(v many-clumps-4 0 worst_texel_error)
  w8=$(v many-clumps-8 0 worst_texel_error)
  few=$(max "$m2" "$m4") fw=$(max "$w2" "$w4")
  check "map error Q=2 $(num "$m2"), Q=4 $(num "$m4"), Q=8 $(num "$m8"): Q=8 / larger $(num "$m8/$few") (> 1.15)" \
    "$m8 > 1.15 * $few"
  check "worst texel Q=2 $(num "$w2"), Q=4 $(num "$w4"), Q=8 $(num "$w8"): Q=8 / larger $(num "$w8/$fw") (> 1.6)" \
    "$w8 > 1.6 * $fw"
}

claim_one_stray_strand() {
  # stability::one_stray_strand_fails_dom_in_a_band_of_texels (Sintorn & Assarsson Fig. 4/5a, the tail)
  shadows one-stray stray-strand -- dom:layers=3 occupancy
  local pd po md mo sd so
  pd=$(v one-stray 0 texel_error_p99) po=$(v one-stray 1 texel_error_p99)
  md=$(v one-stray 0 map_error) mo=$(v one-stray 1 map_error)
  sd=$(v one-stray 0 share_texels_over_0.1) so=$(v one-stray 1 share_texels_over_0.1)
  check "p99 texel DOM-3 $(num "$pd") / occupancy $(num "$po") = $(num "$pd/$po") (> 4)" "$pd > 4 * $po"
  check "p99 ratio / map error ratio $(num "($pd/$po)/($md/$mo)") (> 1.3)" "$pd / $po > 1.3 * $md / $mo"
  check "texels over 0.1: DOM-3 $(num "100*$sd") %, occupancy $(num "100*$so") % (> 5 %, < 0.5 %)" \
    "$sd > 0.05 && $so < 0.005"
}

claim_adsm() {
  # stability::adsm_constant_spacing_against_the_reference (TressFX ADSM)
  shadows adsm-stray stray-strand -- adsm occupancy
  shadows adsm-mixed mixed-sizes -- adsm occupancy adsm:fiber_spacing=0.03125 osm:slices=16
  local a o am om f50 o50 f95 o95 fmem omem fgeom
  a=$(v adsm-stray 0 map_error) o=$(v adsm-stray 1 map_error)
  am=$(v adsm-mixed 0 map_error) om=$(v adsm-mixed 1 map_error)
  f50=$(v adsm-mixed 2 texel_error_p50) o50=$(v adsm-mixed 3 texel_error_p50)
  f95=$(v adsm-mixed 2 texel_error_p95) o95=$(v adsm-mixed 3 texel_error_p95)
  fmem=$(v adsm-mixed 2 memory_bytes) omem=$(v adsm-mixed 3 memory_bytes) fgeom=$(v adsm-mixed 2 geometry_passes)
  check "stray-strand map error ADSM $(num "$a") / occupancy $(num "$o") = $(num "$a/$o") (> 5)" "$a > 5 * $o"
  check "mixed-sizes map error ADSM $(num "$am") / occupancy $(num "$om") = $(num "$am/$om") (> 5)" "$am > 5 * $om"
  check "median texel ADSM(0.03125) $(num "$f50") / OSM-16 $(num "$o50") = $(num "$f50/$o50") (< 0.85)" \
    "$f50 < 0.85 * $o50"
  check "memory $fmem vs $omem bytes (x4 <), geometry passes $fgeom (0)" "$fmem * 4 < $omem && $fgeom == 0"
  check "p95 texel ADSM(0.03125) $(num "$f95") / OSM-16 $(num "$o95") = $(num "$f95/$o95") (> 1)" "$f95 > $o95"
}

# avsm DIR: stability_avsm::check on a run of the four AVSM configurations.
avsm() {
  local d=$1 i n4 n4s n16 n16s w4 w4s w16 w16s
  for i in 0 2; do
    local md ms wd ws
    md=$(v "$d" $i map_error) ms=$(v "$d" $((i + 1)) map_error)
    wd=$(v "$d" $i worst_texel_error) ws=$(v "$d" $((i + 1)) worst_texel_error)
    check "N=$((i == 0 ? 4 : 16)) submission vs depth order: map error $(num "100*($ms/$md-1)") % (|.| in 2..20 %)" \
      "($ms/$md-1)^2 > 0.02^2 && ($ms/$md-1)^2 < 0.2^2"
    check "N=$((i == 0 ? 4 : 16)) submission vs depth order: worst texel $(num "100*($ws/$wd-1)") % (|.| in 5..50 %)" \
      "($ws/$wd-1)^2 > 0.05^2 && ($ws/$wd-1)^2 < 0.5^2"
  done
  n4=$(v "$d" 0 map_error) n4s=$(v "$d" 1 map_error) n16=$(v "$d" 2 map_error) n16s=$(v "$d" 3 map_error)
  w4=$(v "$d" 0 worst_texel_error) w4s=$(v "$d" 1 worst_texel_error)
  w16=$(v "$d" 2 worst_texel_error) w16s=$(v "$d" 3 worst_texel_error)
  check "N=4/N=16 map error $(num "$n4/$n16")x depth, $(num "$n4s/$n16s")x submission (> 8)" \
    "$n4 > 8 * $n16 && $n4s > 8 * $n16s"
  check "N=4/N=16 worst texel $(num "$w4/$w16")x depth, $(num "$w4s/$w16s")x submission (> 4)" \
    "$w4 > 4 * $w16 && $w4s > 4 * $w16s"
}

AVSM=(avsm:nodes=4 avsm:nodes=4,order=submission avsm:nodes=16 avsm:nodes=16,order=submission)

claim_avsm_stray() {
  # stability_avsm::insertion_order_and_node_count_on_stray_strands (Salvi et al. 2010)
  shadows avsm-stray stray-strand -- "${AVSM[@]}"
  avsm avsm-stray
}

claim_avsm_default() {
  # stability_avsm::insertion_order_and_node_count_on_the_default_head (Salvi et al. 2010)
  shadows avsm-default default --set scene.generator.strands=2000 --set render.map_resolution=256 -- "${AVSM[@]}"
  avsm avsm-default
}

claim_msm_six_moments() {
  # stability_msm::six_moments_fit_better_than_four (MBOIT §5 / Peters et al. 2017)
  local preset ratio m4 m6 s4 s6
  for preset in default:0.97 stray-strand:0.9; do
    ratio=${preset#*:} preset=${preset%:*}
    shadows "msm-$preset" "$preset" -- msm msm:moments=6,bias=5e-6
    m4=$(v "msm-$preset" 0 map_error) m6=$(v "msm-$preset" 1 map_error)
    s4=$(v "msm-$preset" 0 shading_error) s6=$(v "msm-$preset" 1 shading_error)
    check "$preset map error MSM-6 $(num "$m6") / MSM-4 $(num "$m4") = $(num "$m6/$m4") (< $ratio)" \
      "$m6 < $ratio * $m4"
    check "$preset shading MSM-6 $(num "$s6") / MSM-4 $(num "$s4") = $(num "$s6/$s4") (< $ratio)" \
      "$s6 < $ratio * $s4"
  done
}

claim_fom_gpu() {
  # stability_fom::straight_grazing_rings_fourier_opacity_maps_less_with_more_terms, its GPU part (Jansen & Bavoil
  # §7.3); the unclamped ringing is read from the CPU model, which the CLI does not expose.
  shadows fom straight-grazing -- fom:terms=2,window=plain fom:terms=4,window=plain fom:terms=8,window=plain \
    fom:terms=16,window=plain osm:slices=16
  local i k=2 w0 w1 m0 m1
  for i in 0 1 2; do
    w0=$(v fom $i worst_texel_error) w1=$(v fom $((i + 1)) worst_texel_error)
    m0=$(v fom $i map_error) m1=$(v fom $((i + 1)) map_error)
    check "K=$k->$((2 * k)) worst texel $(num "$w0") -> $(num "$w1") = $(num "$w1/$w0") (< 0.97)" "$w1 < 0.97 * $w0"
    check "K=$k->$((2 * k)) map error $(num "$m0") -> $(num "$m1") = $(num "$m1/$m0") (< 0.88)" "$m1 < 0.88 * $m0"
    k=$((2 * k))
  done
}

claim_tc1() {
  # transparency_claims::occupancy_order_is_nearly_exact_and_weighted_average_is_dull (Sintorn & Assarsson 2009
  # §3.4, TC-1 and TC-3)
  local dir=$OUT/$FIT/tc1
  "$HAIRLAB" measure transparency --preset transparency-head --frames 0 --set "light.fit=$FIT" \
    --set scene.generator.strands=1500 --set render.map_resolution=256 \
    --technique occupancy-order --technique weighted-average --technique wboit --out "$dir" >"$dir.log" 2>&1 ||
    { echo "failed: see $dir.log" >&2; exit 1; }
  t() { jq -r ".rows[$1][\"$2\"]" "$dir/transparency.json"; }
  local deep o w b os ws ol wl o8
  deep=$(jq -r .max_depth_complexity "$dir/transparency.json")
  o=$(t 0 rmse_hair) w=$(t 1 rmse_hair) b=$(t 2 rmse_hair) os=$(t 0 ssim_hair) ws=$(t 1 ssim_hair)
  ol=$(t 0 mean_luminance_ratio) wl=$(t 1 mean_luminance_ratio) o8=$(t 0 share_over_8)
  check "deepest pixel $deep (>= 32)" "$deep >= 32"
  check "hair RMSE occupancy-order $(num "$o") / weighted-average $(num "$w") = $(num "$o/$w") (< 0.5)" "$o < 0.5 * $w"
  check "hair RMSE occupancy-order $(num "$o") < WBOIT $(num "$b")" "$o < $b"
  check "SSIM occupancy-order $(num "$os") > weighted-average $(num "$ws")" "$os > $ws"
  check "luminance weighted-average $(num "$wl") (< 0.99), occupancy-order $(num "$ol") (nearer 1)" \
    "$wl < 0.99 && ($ol - 1)^2 < ($wl - 1)^2"
  check "occupancy-order pixels off by > 8/255 $(num "100*$o8") % (< 0.5 %)" "$o8 < 0.005"
}

for claim in $CLAIMS; do
  for FIT in $FITS; do
    mkdir -p "$OUT/$FIT"
    FAILED=0 CHECKS=0
    start=$SECONDS
    say "== $claim, light.fit=$FIT"
    "claim_${claim//-/_}"
    say "  [$FIT] $claim: $([[ $FAILED == 0 ]] && echo holds || echo "FAILS $FAILED of $CHECKS checks") ($((SECONDS - start)) s)"
  done
done
