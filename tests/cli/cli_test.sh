#!/usr/bin/env bash
# End-to-end checks of the `penumbra` CLI: outputs written, stats keys present, and every kind of
# bad input answered by a one-line error and a non-zero exit (never a crash).
#   cli_test.sh PENUMBRA_BINARY DATA_DIR
set -uo pipefail
bin="$1"
data="$2"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
export PENUMBRA_NO_PROGRESS=1
passed=0
failed=0

ok() { passed=$((passed + 1)); }
bad() {
  echo "FAIL: $*"
  failed=$((failed + 1))
}

# expect_error "substring" args...: the error contract — exit code 1 (not a crash, not CLI11's
# 105/106/109), exactly one line starting `penumbra:` on stderr, as its last line, holding the
# substring.
expect_error() {
  local want="$1"
  shift
  local err
  err="$(timeout 60 "$bin" "$@" 2>&1 >/dev/null)"
  local rc=$?
  local lines
  lines="$(grep -c '^penumbra:' <<<"$err")"
  if [ "$rc" -ne 1 ]; then
    bad "'${*:0:200}' exited $rc (want 1): ${err:0:400}"
  elif [ "$lines" -ne 1 ] || ! tail -n 1 <<<"$err" | grep -q '^penumbra: '; then
    bad "'${*:0:200}': want exactly one 'penumbra:' line, last: ${err:0:400}"
  elif ! grep -qF -- "$want" <<<"$err"; then
    bad "'$*': message lacks '$want': $err"
  else
    ok
  fi
}

# A render with two methods: folders, table, files, stats keys.
if "$bin" render --scene quad --method exact --method raytrace --samples 4 --size 48x32 \
  --aov position,normal,depth --out "$work/r" >"$work/table.txt" 2>"$work/err.txt"; then
  for f in exact/beauty.png exact/visibility.exr exact/stats.json raytrace/error_vs_exact.png \
    raytrace/stats.json summary.md summary.json position.exr normal.exr depth.exr; do
    [ -s "$work/r/$f" ] && ok || bad "render did not write $f"
  done
  grep -q "| raytrace |" "$work/table.txt" && ok || bad "no table row for raytrace"
  for key in '"method"' '"parameters"' '"times_ms"' '"total"' '"counters"' '"scene"' '"error_vs_exact"'; do
    grep -q "$key" "$work/r/raytrace/stats.json" && ok || bad "stats.json lacks $key"
  done
else
  bad "render failed: $(cat "$work/err.txt")"
fi

# The frame block accounts for the whole process: its stages sum to elapsed_ms, the work run beside
# them (the G-buffer's layers beside the load and BVH with --size, the irradiance beside the
# methods) listed apart in "overlapped", not summed; the breakdown line names it.
frame_adds_up() {
  awk '/^  "frame": \{/ { f = 1; next }
       f && /^  \}/ { f = 0 }
       f && /^    "overlapped": \{/ { o = 1 }
       f && /^    "[a-z_]+_ms": / { gsub(/[",:]/, ""); if ($1 == "elapsed_ms") e = $2; else s += $2 }
       END { exit !(o && e > 0 && (s - e) * (s - e) < 1e-6 * e * e) }' "$1"
}
for d in exact raytrace; do
  frame_adds_up "$work/r/$d/stats.json" && ok || bad "$d/stats.json: frame stages do not sum to elapsed_ms"
done
grep -q '"gbuffer_layers_ms"' "$work/r/exact/stats.json" && ok || bad "no overlapped gbuffer_layers_ms"
tail -n 1 "$work/err.txt" | grep -q '^frame: .*BVH [0-9]* (beside load to BVH: G-buffer layers [0-9]*)' &&
  ok || bad "frame line lacks the overlapped stages: $(tail -n 1 "$work/err.txt")"

# compare: the documented keys, compare.json and the error map.
if "$bin" compare "$work/r/exact/visibility.exr" "$work/r/raytrace/visibility.exr" --out "$work/c" >"$work/cmp.txt"; then
  for key in mean_abs_shadowed mean_abs rmse max_abs psnr frac_over_1_255 frac_over_1_16; do
    grep -q "^$key" "$work/cmp.txt" && ok || bad "compare did not print $key"
    grep -q "\"$key\"" "$work/c/compare.json" && ok || bad "compare.json lacks $key"
  done
  [ -s "$work/c/error_map.png" ] && ok || bad "no error map"
else
  bad "compare failed"
fi

# PFM output round-trips through compare.
if "$bin" render --scene quad --method raytrace --samples 2 --size 24x24 --float-format pfm --out "$work/p" 2>/dev/null &&
  "$bin" compare "$work/p/visibility.pfm" "$work/p/visibility.pfm" >"$work/self.txt" &&
  grep -q "^max_abs *0.0$" "$work/self.txt"; then
  ok
else
  bad "PFM render + compare with itself"
fi

# (Captured first: with pipefail, `grep -q` closing the pipe early would fail the writer.)
listing="$("$bin" list)"
grep -q "raytrace" <<<"$listing" && ok || bad "list lacks raytrace"
info="$("$bin" info quad)"
grep -q "closed 2-manifold\|open/non-manifold" <<<"$info" && ok || bad "info lacks topology"
! grep -q "^animation" <<<"$info" && ok || bad "info shows an animation for a still scene"
info="$("$bin" info flag)"
grep -q "^animation  0 s to 2 s at 24 fps: frames 0..48; moves geometry (1 mesh(es))$" <<<"$info" &&
  ok || bad "info lacks flag's animation: $(grep '^animation' <<<"$info")"
# Names from the file are escaped: a newline in a mesh name does not start a forged line.
printf '%s' '{"camera":{"position":[0,2,4],"target":[0,0,0]},"materials":[{"name":"g"}],
 "meshes":[{"name":"a\nmesh      forged","shape":"quad","center":[0,0,0],"edge_u":[0,0,4],"edge_v":[4,0,0],"material":"g"}],
 "lights":[{"type":"rect","center":[0,3,0],"edge_u":[1,0,0],"edge_v":[0,0,1],"radiance":5}]}' >"$work/nl_name.json"
info="$("$bin" info "$work/nl_name.json")"
[ "$(grep -c '^mesh ' <<<"$info")" = 1 ] && grep -q 'a\\nmesh' <<<"$info" && ok || bad "info echoes a raw newline"

# report: one page and its images; scene: a JSON file that renders; a model file as --scene.
if "$bin" report --scene quad --method raytrace --size 32x32 --samples 2 --out "$work/rep" \
  >"$work/rep.txt" 2>/dev/null && grep -q "index.html" "$work/rep.txt" &&
  [ -s "$work/rep/quad/raytrace_abs.png" ] && grep -q "### quad" "$work/rep/results.md"; then
  ok
else
  bad "report"
fi
if "$bin" scene --scene fence --out "$work/sc/fence.json" >/dev/null &&
  "$bin" render --scene "$work/sc/fence.json" --method exact --size 32x32 --out "$work/sc/r" \
    >/dev/null 2>&1 && [ -s "$work/sc/r/beauty.png" ]; then
  ok
else
  bad "scene export + render"
fi
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >"$work/tetra.obj"
if "$bin" render --scene "$work/tetra.obj" --method exact --size 32x32 --light-size 0.3 --up z \
  --out "$work/obj" >/dev/null 2>&1 && [ -s "$work/obj/beauty.png" ]; then
  ok
else
  bad "render a model file"
fi
expect_error "sweep" report --scene quad --method exact --sweep nosuch --out "$work/x"
expect_error "light-size" render --scene "$work/tetra.obj" --method exact --light-size -1 --out "$work/x"

# Sequences (render --frames): the range is checked before the scene is read, a still scene is
# refused, --fps needs --frames.
expect_error "the scene is still" render --scene quad --method gears --frames 0:3 --size 16x16 --out "$work/x"
expect_error "STEP must be at least 1" render --scene nosuchscene --method gears --frames 0:3:0 --out "$work/x"
expect_error "expected START:END" render --scene nosuchscene --method gears --frames 3 --out "$work/x"
expect_error "must be a whole number" render --scene nosuchscene --method gears --frames a:3 --out "$work/x"
expect_error "must be a whole number" render --scene nosuchscene --method gears --frames -1:3 --out "$work/x"
expect_error "END is before START" render --scene nosuchscene --method gears --frames 5:2 --out "$work/x"
expect_error "--fps applies to a sequence" render --scene quad --method gears --fps 30 --out "$work/x"
expect_error "fps" render --scene quad --method gears --frames 0:1 --fps 0 --out "$work/x"
# With an animated built-in scene (once the scene side provides them): one entry per frame and
# method in frames.json, and a range beyond the animation refused.
if "$bin" list 2>/dev/null | grep -q "fence_spin"; then
  if "$bin" render --scene fence_spin --method exact --method gears --frames 0:2 --size 32x32 \
    --samples 2 --out "$work/seq" >/dev/null 2>"$work/err.txt"; then
    python3 -c 'import json,math,sys; d=json.load(open(sys.argv[1])); e=d["frames"]; assert len(e)==6, len(e); assert all(math.isfinite(x["total_ms"]) for x in e)' \
      "$work/seq/frames.json" && ok || bad "frames.json: not one finite entry per frame and method"
    [ -s "$work/seq/gears/frame_0002/beauty.png" ] && ok || bad "no gears/frame_0002/beauty.png"
    if command -v ffmpeg >/dev/null; then
      [ -s "$work/seq/compare.mp4" ] && ok || bad "ffmpeg installed but no compare.mp4"
    fi
  else
    bad "render --frames fence_spin failed: $(cat "$work/err.txt")"
  fi
  expect_error "the animation has frames" render --scene fence_spin --method gears --frames 0:100000 --size 16x16 --out "$work/x"
fi

# Bad input: clear one-line errors.
expect_error "unknown scene" render --scene nosuchscene --method exact --out "$work/x"
expect_error "unknown method" render --scene quad --method nosuch --out "$work/x"
# A device index beyond size_t was "internal error: stoul"; it matches no device (with Vulkan) or
# names the missing backend (without).
expect_error "vulkan" render --scene quad --method gears --backend vulkan \
  --vk-device 99999999999999999999 --size 16x16 --out "$work/x"
expect_error "has no option" render --scene quad --method raytrace --set raytrace.nosuch=1 --out "$work/x"
expect_error "is not one of" render --scene quad --method raytrace --set raytrace.path=warp --out "$work/x"
expect_error "expected method.option=value" render --scene quad --method raytrace --set nodot --out "$work/x"
expect_error "is not one of" render --scene fence --method dcs --set dcs.alpha=holes --out "$work/x"
# Soft textured shadow volumes: counters in stats.json, alpha=opaque as the fallback option.
if "$bin" render --scene fence --method dcs --method wedges --set wedges.alpha=opaque --size 32x32 \
  --samples 2 --out "$work/stsv" >/dev/null 2>&1 &&
  grep -q '"stsv_sample_lookups"' "$work/stsv/dcs/stats.json" &&
  ! grep -q '"stsv_sample_lookups"' "$work/stsv/wedges/stats.json"; then
  ok
else
  bad "stsv counters / alpha=opaque"
fi
expect_error "--size" render --scene quad --method raytrace --size 0x10 --out "$work/x"
expect_error "pattern" render --scene quad --method raytrace --pattern blue --out "$work/x"
expect_error "samples" render --scene quad --method raytrace --samples 0 --out "$work/x"
expect_error "scene file" render --scene "$data/scenes/broken/syntax_missing_comma.json" --method exact --out "$work/x"
expect_error "cannot" compare "$work/nonexistent.exr" "$work/r/exact/visibility.exr"
printf 'garbage' >"$work/garbage.exr"
expect_error "garbage.exr" compare "$work/garbage.exr" "$work/r/exact/visibility.exr"
expect_error "info" info

# The error contract for usage errors: CLI11's own errors are one `penumbra:` line and exit 1 too.
expect_error "unknown command 'rendr' (did you mean 'render'?)" rendr --scene quad
expect_error "a command is required" 
expect_error "--out is required" render --scene quad --method exact
expect_error "--scene is required" render --method exact --out "$work/x"
expect_error "unknown option '--bogus-flag'" render --bogus-flag
expect_error "--float-format" render --scene quad --method exact --float-format tiff --out "$work/x"
expect_error "did you mean 'exact'?" render --scene quad --method exct --out "$work/x"
expect_error "did you mean 'spheres'?" render --scene sphere --method exact --out "$work/x"
expect_error "did you mean 'render'?" rnder
# Integer options: parsed once, whole string, base 10.
expect_error "'0x10' is not a base-10 integer" render --scene quad --method ssm --set ssm.resolution=0x10 --out "$work/x"
expect_error "'0x20' is not a base-10 integer" render --scene quad --method gears --set gears.chunk=0x20 --out "$work/x"
expect_error "'1e3' is not a base-10 integer" render --scene quad --method shadow_map --set shadow_map.resolution=1e3 --out "$work/x"
# User strings are escaped and cut: no forged second line, no 3 MB echo.
expect_error "unknown key 'fov\\nPWNED" render --scene "$data/scenes/broken/control_char_key.json" --method exact --out "$work/x"
long_key="$(head -c 100000 /dev/zero | tr '\0' k)"  # (one argument may hold at most 128 KB)
err="$("$bin" render --scene quad --method raytrace --set "raytrace.$long_key=1" --out "$work/x" 2>&1)"
[ "${#err}" -lt 1000 ] && grep -q "100000 bytes" <<<"$err" && ok || bad "a 3 MB option key was echoed whole (${#err} bytes)"
expect_error "has no option" render --scene quad --method raytrace --set "raytrace.a$(printf '\033')[2Jb=1" --out "$work/x"
# Special files are refused at once, not read forever.
mkfifo "$work/fifo.json"
expect_error "not a regular file" render --scene "$work/fifo.json" --method exact --out "$work/x"
expect_error "not a regular file" info "$work/fifo.json"
printf '{"camera":{"position":[0,2,4],"target":[0,0,0]},"materials":[{"name":"g"}],"meshes":[{"file":"/dev/zero","material":"g"}],"lights":[{"type":"point","center":[0,3,0],"radiance":1}]}' >"$work/zero_mesh.json"
expect_error "cannot load mesh '/dev/zero': not a regular file" info "$work/zero_mesh.json"
# A frame that cannot fit in memory is refused up front with the estimate, not by bad_alloc.
expect_error "needs about" render --scene quad --method all --size 16384x16384 --samples 64 --shading integrate --out "$work/x"
# Write failures: exit 1, and nothing half-written under the final name.
mkdir -p "$work/w/beauty.png"
expect_error "cannot write" render --scene quad --method raytrace --samples 1 --size 8x8 --out "$work/w"
[ -z "$(find "$work/w" -name '*.partial-*')" ] && ok || bad "a temporary file was left behind"
: >"$work/a_file"
expect_error "cannot create output folder" compare "$work/r/exact/visibility.exr" "$work/r/raytrace/visibility.exr" --out "$work/a_file/x"
err="$("$bin" list 2>&1 >/dev/full)"
rc=$?
[ "$rc" -eq 1 ] && [ "$(grep -c '^penumbra: error: cannot write to standard output' <<<"$err")" -eq 1 ] && ok ||
  bad "list >/dev/full: exit $rc: $err"
expect_error "cannot compare images of different sizes" compare "$work/r/exact/visibility.exr" "$work/p/visibility.pfm"
# Numbers read strictly (whole value, base 10, in range): no 32-bit wrap, no hex, no negative
# seed taken modulo 2^64, no empty value read as 0 or ignored.
expect_error "--size" render --scene quad --method raytrace --size 4294967297x1 --out "$work/x"
expect_error "--size" render --scene quad --method raytrace --size '' --out "$work/x"
expect_error "--size" render --scene quad --method raytrace --size ' 16x16' --out "$work/x"
expect_error "--size" report --scene quad --method raytrace --size 16x-16 --out "$work/x"
expect_error "'0x10' is not a base-10 integer" render --scene quad --method raytrace --samples 0x10 --out "$work/x"
expect_error "65 is outside [1, 64]" render --scene quad --method raytrace --samples 65 --out "$work/x"
expect_error "'-1' is not a base-10 integer" render --scene quad --method gears --seed -1 --out "$work/x"
expect_error "'' is not a base-10 integer" render --scene quad --method gears --seed '' --out "$work/x"
expect_error "'18446744073709551616' is not a base-10 integer" render --scene quad --method gears --seed 18446744073709551616 --out "$work/x"
expect_error "'-3' is not a base-10 integer" report --scene quad --method raytrace --seed -3 --out "$work/x"
for scale in nan -1 '' inf 0; do
  expect_error "is not a finite number > 0" compare "$work/r/exact/visibility.exr" "$work/r/exact/visibility.exr" --error-scale "$scale"
  expect_error "is not a finite number > 0" report --scene quad --method raytrace --error-scale "$scale" --out "$work/x"
done
# The largest seed and a leading zero (CLI11 alone reads 010 as octal 8) are taken as written.
if "$bin" render --scene quad --method gears --pattern poisson --samples 2 --size 8x8   --seed 18446744073709551615 --out "$work/seed" >/dev/null 2>&1 &&
  grep -q '"seed": 18446744073709551615' "$work/seed/stats.json" &&
  "$bin" render --scene quad --method gears --pattern poisson --samples 2 --size 8x8 --seed 010 \
    --out "$work/seed10" >/dev/null 2>&1 && grep -q '"seed": 10' "$work/seed10/stats.json"; then
  ok
else
  bad "--seed 2^64-1 / 010 not taken as written: $(grep '"seed"' "$work/seed/stats.json" "$work/seed10/stats.json" 2>&1)"
fi
# Every argument checked before the first scene is read or rendered, each named correctly.
expect_error "--aov: an empty AOV name in ','" render --scene quad --method exact --size 16x16 --samples 1 --aov , --float-format pfm --out "$work/x"
expect_error "--aov: unknown AOV 'normals' (did you mean 'normal'?)" render --scene quad --method exact --aov position,normals --out "$work/x"
err="$("$bin" render --scene quad --method exact --aov bogus --out "$work/x" 2>&1)"
grep -q "^scene " <<<"$err" && bad "an unknown AOV was reported after the scene was loaded: $err" || ok
err="$("$bin" report --scene quad --scene nosuch --method raytrace --size 16x16 --samples 1 --out "$work/rep2" 2>&1)"
rc=$?
[ "$rc" -eq 1 ] && grep -q "unknown scene 'nosuch'" <<<"$err" && ! grep -q "raytrace .* ms" <<<"$err" &&
  [ ! -e "$work/rep2/quad" ] && ok || bad "report --scene nosuch after quad: exit $rc, rendered first: $err"
expect_error "gears.grid: 'abc'" render --scene quad --method raytrace --set gears.grid=abc --out "$work/x"
expect_error "(patterns: grid, stratified, decorrelated, interleaved, halton, poisson)" render --scene quad --method raytrace --pattern random --out "$work/x"
expect_error "unknown option '--sample' (did you mean '--samples'?)" render --scene quad --method raytrace --sample 4 --out "$work/x"
expect_error "unknown option '--methd' (did you mean '--method'?)" report --scene quad --methd raytrace --out "$work/x"
# info takes the scene positionally or as --scene, as every other command does.
"$bin" info --scene quad | grep -q "^triangles" && ok || bad "info --scene quad"
expect_error "a scene is required" info
# Progress written to a log or a pipe: plain newline-terminated lines, no carriage returns.
"$bin" render --scene quad --method raytrace --method shadow_map --samples 1 --size 16x16 \
  --out "$work/log" >/dev/null 2>"$work/log.txt"
if grep -q $'\r' "$work/log.txt"; then
  bad "stderr to a file holds carriage returns: $(tr '\r' '^' <"$work/log.txt" | head -5)"
else
  grep -q "^  shadow_map  .* ms$" "$work/log.txt" && ok || bad "no plain line per method: $(cat "$work/log.txt")"
fi
"$bin" report --scene quad --method raytrace --samples 1 --size 16x16 --out "$work/replog" \
  >/dev/null 2>"$work/replog.txt"
grep -q $'\r' "$work/replog.txt" && bad "report stderr holds carriage returns" || ok
# --help shows defaults.
"$bin" render --help | grep -q -- "--samples.*=16" && ok || bad "render --help lacks the --samples default"

echo "cli: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
