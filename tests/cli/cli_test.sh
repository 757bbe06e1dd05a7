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

# expect_error "substring" args...: exit code 1 (not a crash) and the substring on stderr.
expect_error() {
  local want="$1"
  shift
  local err
  err="$("$bin" "$@" 2>&1 >/dev/null)"
  local rc=$?
  if [ "$rc" -ne 1 ] && [ "$rc" -ne 105 ] && [ "$rc" -ne 106 ] && [ "$rc" -ne 109 ]; then
    bad "'$*' exited $rc (want a clean error): $err"
  elif ! grep -q -- "$want" <<<"$err"; then
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

# Bad input: clear one-line errors.
expect_error "unknown scene" render --scene nosuchscene --method exact --out "$work/x"
expect_error "unknown method" render --scene quad --method nosuch --out "$work/x"
expect_error "has no option" render --scene quad --method raytrace --set raytrace.nosuch=1 --out "$work/x"
expect_error "is not one of" render --scene quad --method raytrace --set raytrace.path=warp --out "$work/x"
expect_error "expected method.option=value" render --scene quad --method raytrace --set nodot --out "$work/x"
expect_error "--size" render --scene quad --method raytrace --size 0x10 --out "$work/x"
expect_error "pattern" render --scene quad --method raytrace --pattern blue --out "$work/x"
expect_error "samples" render --scene quad --method raytrace --samples 0 --out "$work/x"
expect_error "scene file" render --scene "$data/scenes/broken/syntax_missing_comma.json" --method exact --out "$work/x"
expect_error "cannot" compare "$work/nonexistent.exr" "$work/r/exact/visibility.exr"
printf 'garbage' >"$work/garbage.exr"
expect_error "garbage.exr" compare "$work/garbage.exr" "$work/r/exact/visibility.exr"
expect_error "info" info

echo "cli: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
