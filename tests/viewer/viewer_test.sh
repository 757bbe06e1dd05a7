#!/usr/bin/env bash
# `penumbra view` end to end, under Xvfb with Mesa's software OpenGL (64² frames, K = 4: seconds):
#  - after light (centre, size, shape, radiance) and camera edits and `wait`, save_visibility
#    equals `penumbra render` of the save_scene file, same method and samples (max |ΔV| <= 1e-6),
#    for exact, gears and pcss;
#  - in the visibility view the image shows V exactly, two light positions' screenshots differ
#    where V changed and only there, and the panel beside the image is drawn;
#  - the error, signed-error and split views and `set` run; the error against a ray-traced
#    reference is 0 on the method's own samples; --backend vulkan gives render's GPU frame; an
#    animated scene at `time T` is render's frame at T; bad input is one line and exit 1.
# Exits 77 (ctest: skipped) without xvfb-run.
#   viewer_test.sh PENUMBRA_BINARY VIEWER_PROBE OUTPUT_DIR
set -uo pipefail
bin="$(realpath "$1")"
probe="$(realpath "$2")"
out="$3"
if ! command -v xvfb-run >/dev/null 2>&1; then
  echo "SKIPPED: no xvfb-run on PATH (scripts/setup.sh installs xvfb)"
  exit 77
fi
rm -rf "$out"
mkdir -p "$out"
cd "$out" || exit 1
export PENUMBRA_NO_PROGRESS=1 LIBGL_ALWAYS_SOFTWARE=1
failed=0
fail() {
  echo "FAIL: $*"
  failed=1
}
# The image (64²) is drawn 8 times enlarged at the window's top-left; the panel starts at x = 512.
scale=8
panel_x=512
view() {  # view LOG ARGS...: runs the viewer on a virtual display
  local log="$1"
  shift
  # The viewer's own exit status, written beside the log: xvfb-run's clean-up (`set -e`, xauth)
  # sometimes failed under load and replaced it (exit 5 for a viewer that had returned 1).
  rm -f "$log.rc"
  timeout 300 xvfb-run -a -s "-screen 0 1280x1024x24" sh -c '"$@"; echo $? >"$0"' "$log.rc" \
    "$bin" view --size 64x64 --samples 4 "$@" >"$log" 2>&1
  local code=$?
  if [ -s "$log.rc" ]; then code="$(cat "$log.rc")"; fi
  return "$code"
}
max_abs() {  # max_abs A.exr B.exr: compare's max |ΔV|
  "$bin" compare "$1" "$2" --out "cmp_$(basename "$1" .exr)" >/dev/null 2>&1 &&
    sed -n 's/.*"max_abs": \([^,]*\),.*/\1/p' "cmp_$(basename "$1" .exr)/compare.json"
}

# 1. The saved visibility is what `render` computes from the saved scene (each method with another
#    light shape: a change of shape is written to the scene too).
declare -A shape=([exact]=sphere [gears]=disk [pcss]=rect)
for method in exact gears pcss; do
  cat >"edit_$method.txt" <<SCRIPT
camera_orbit 25 10
light_center 0.25 2.1 -0.15
light_scale 0.7
light_shape ${shape[$method]}
light_radiance 2
wait
save_visibility view_$method.exr
save_scene scene_$method.json
SCRIPT
  if ! view "view_$method.log" --scene quad --method "$method" --script "edit_$method.txt"; then
    fail "$method: the viewer failed: $(cat "view_$method.log")"
    continue
  fi
  if ! "$bin" render --scene "scene_$method.json" --method "$method" --samples 4 \
    --out "render_$method" >"render_$method.log" 2>&1; then
    fail "$method: render of the saved scene failed: $(cat "render_$method.log")"
    continue
  fi
  d="$(max_abs "view_$method.exr" "render_$method/visibility.exr")"
  echo "$method: max |V_view - V_render| = $d"
  awk -v d="$d" 'BEGIN { exit !(d != "" && d <= 1e-6) }' || fail "$method: max |dV| = '$d' > 1e-6"
done

# 2. Two light positions in the visibility view.
cat >moves.txt <<'SCRIPT'
view visibility
light_center 0.3 2.0 0.1
wait
screenshot a.png
save_visibility a.exr
light_center -0.35 2.0 -0.3
wait
screenshot b.png
save_visibility b.exr
quit
SCRIPT
if view moves.log --scene quad --method gears --script moves.txt; then
  "$probe" match a.png a.exr "$scale" || fail "the visibility view of position A is not V"
  "$probe" match b.png b.exr "$scale" || fail "the visibility view of position B is not V"
  "$probe" moved a.png b.png a.exr b.exr "$scale" ||
    fail "the screenshots do not differ exactly where the shadow moved"
  "$probe" panel a.png "$panel_x" || fail "the panel is blank"
else
  fail "the light-move script failed: $(cat moves.log)"
fi

# 3. A drag: moves 20 ms apart are shown as previews (16² frames), the frame after `wait` is the
#    full one of the last position, whatever previews were still running.
awk 'BEGIN { print "wait"; for (i = 0; i < 12; i++) printf "light_center %.2f 2 0\nsleep 20\n", -0.6 + 0.1 * i;
             print "wait"; print "save_visibility drag.exr"; print "save_scene drag.json" }' >drag.txt
if view drag.log --scene quad --method gears --script drag.txt; then
  previews="$(sed -n 's/.*(\([0-9]*\) of them previews).*/\1/p' drag.log)"
  echo "drag: $previews of 12 moves first shown by a preview"
  [ -n "$previews" ] && [ "$previews" -ge 1 ] || fail "no preview during the drag: $(cat drag.log)"
  "$bin" render --scene drag.json --method gears --samples 4 --out render_drag >render_drag.log 2>&1 ||
    fail "render of the dragged scene failed: $(cat render_drag.log)"
  d="$(max_abs drag.exr render_drag/visibility.exr)"
  echo "drag: max |V_view - V_render| = $d"
  awk -v d="$d" 'BEGIN { exit !(d != "" && d <= 1e-6) }' || fail "drag: max |dV| = '$d' > 1e-6"
  tr -d ' \n' <drag.json | grep -q '"lights":\[{"center":\[0.5,2.0,0.0\]' ||
    fail "the saved scene's light is not at the last position"
else
  fail "the drag script failed: $(cat drag.log)"
fi

# 4. The other views, an option, a method switch.
cat >views.txt <<'SCRIPT'
method pcss
set pcss.blocker_samples=8
view error
wait
screenshot error.png
view signed_error
wait
view split exact gears
wait
screenshot split.png
SCRIPT
view views.log --scene quad --method gears --script views.txt ||
  fail "the views script failed: $(cat views.log)"
grep -q "first frame showing each" views.log || fail "no latency summary: $(cat views.log)"

# 5. A ray-traced reference for the error views: on the method's own samples gears has no error at
#    all (the same masks as raytrace); against 16×16 samples it has the sampling error of 4×4.
printf 'view error\nwait\nsave_error err.json\n' >rtref.txt
for k in 4 16; do
  if view "rtref_$k.log" --scene quad --method gears --reference raytrace --reference-samples "$k" \
    --script rtref.txt; then
    mv err.json "err_$k.json"
    grep -q '"reference": "raytrace '"$k"'×'"$k"'"' "err_$k.json" ||
      fail "save_error does not name the reference: $(cat "err_$k.json")"
  else
    fail "the ray-traced reference script failed: $(cat "rtref_$k.log")"
  fi
done
err_field() { sed -n 's/.*"'"$2"'": \([^,]*\),*$/\1/p' "$1"; }
awk -v d="$(err_field err_4.json max_abs)" 'BEGIN { exit !(d != "" && d == 0) }' ||
  fail "gears against raytrace on the same samples: max |dV| = $(err_field err_4.json max_abs)"
awk -v d="$(err_field err_16.json mean_abs)" 'BEGIN { exit !(d > 1e-3) }' ||
  fail "gears 4x4 against raytrace 16x16: mean |dV| = $(err_field err_16.json mean_abs)"

# 6. --backend vulkan (where a Vulkan device exists, lavapipe included): the GPU method's frame
#    after the edits is what `render --backend vulkan` computes from the saved scene.
if "$bin" render --scene quad --size 8x8 --method gears --backend vulkan --out vk_probe \
  >vk_probe.log 2>&1; then
  if view vk.log --scene quad --method gears --backend vulkan --script edit_gears.txt; then
    "$bin" render --scene scene_gears.json --method gears --samples 4 --backend vulkan \
      --out render_vk >render_vk.log 2>&1 || fail "vulkan render failed: $(cat render_vk.log)"
    d="$(max_abs view_gears.exr render_vk/visibility.exr)"
    echo "vulkan gears: max |V_view - V_render| = $d"
    awk -v d="$d" 'BEGIN { exit !(d != "" && d <= 1e-6) }' || fail "vulkan: max |dV| = '$d' > 1e-6"
  else
    fail "the viewer on vulkan failed: $(cat vk.log)"
  fi
  "$bin" view --scene quad --method exact --backend vulkan >vk_exact.log 2>&1
  code=$?
  grep -q "method 'exact' has no Vulkan implementation" vk_exact.log && [ "$code" -eq 1 ] ||
    fail "exact on vulkan: expected one error line, exit 1; got exit $code: $(cat vk_exact.log)"
else
  echo "vulkan: no device, skipped"
fi

# 7. Bad input: one line, exit 1.
# An animated scene at a time: the deforming flag at 0.5 s is frame 12 of `render --frames` (its
# 24 fps); the saved scene is that still pose.
cat >anim.txt <<'SCRIPT'
time 0.5
wait
save_visibility anim.exr
save_scene anim.json
SCRIPT
if view anim.log --scene flag --method gears --script anim.txt &&
  "$bin" render --scene flag --method gears --samples 4 --size 64x64 --frames 12:12 \
    --out render_anim >render_anim.log 2>&1 &&
  "$bin" render --scene anim.json --method gears --samples 4 --out render_anim_still \
    >render_anim_still.log 2>&1; then
  d="$(max_abs anim.exr render_anim/gears/frame_0012/visibility.exr)"
  s="$(max_abs anim.exr render_anim_still/visibility.exr)"
  echo "flag at 0.5 s: max |V_view - V_frame_12| = $d, against its saved still = $s"
  awk -v d="$d" -v s="$s" 'BEGIN { exit !(d != "" && d <= 1e-6 && s != "" && s <= 1e-6) }' ||
    fail "flag at 0.5 s: max |dV| = '$d' (frame 12), '$s' (saved still) > 1e-6"
else
  fail "the animation script failed: $(cat anim.log render_anim.log render_anim_still.log)"
fi

# Playback: the time runs while it plays (the frame after about 0.4 s is not the rest pose's), and
# the frame it settles on when paused is render's of the saved still.
cat >play.txt <<'SCRIPT'
play
sleep 400
pause
wait
save_visibility played.exr
save_scene played.json
SCRIPT
if view play.log --scene flag --method gears --script play.txt &&
  "$bin" render --scene played.json --method gears --samples 4 --out render_played \
    >render_played.log 2>&1 &&
  "$bin" render --scene flag --method gears --samples 4 --size 64x64 --out render_rest \
    >render_rest.log 2>&1; then
  d="$(max_abs played.exr render_played/visibility.exr)"
  m="$(max_abs played.exr render_rest/visibility.exr)"
  echo "played: max |V_view - V_saved| = $d, against the rest pose = $m"
  awk -v d="$d" -v m="$m" 'BEGIN { exit !(d != "" && d <= 1e-6 && m != "" && m > 1e-3) }' ||
    fail "playback: max |dV| = '$d' against its still (> 1e-6) or '$m' against the rest (no motion)"
else
  fail "the playback script failed: $(cat play.log render_played.log render_rest.log)"
fi

expect_error() {  # expect_error PATTERN LOG: exit 1 and one 'penumbra: error:' line matching
  local code="$1" pattern="$2" log="$3"
  if [ "$code" -ne 1 ] || [ "$(wc -l <"$log")" -ne 1 ] || ! grep -q "penumbra: error: .*$pattern" "$log"; then
    fail "expected one error line matching '$pattern', exit 1; got exit $code: $(cat "$log")"
  fi
}
printf 'light_center 0 2 0\nzoom 3\n' >unknown.txt
"$bin" view --scene quad --script unknown.txt >unknown.log 2>&1
expect_error $? "unknown.txt':2: unknown command 'zoom'" unknown.log
printf 'set nonsense=1\n' >badset.txt
view badset.log --scene quad --method gears --script badset.txt
expect_error $? "badset.txt':1: method 'gears' has no option 'nonsense'" badset.log
printf 'light 1\n' >badlight.txt
view badlight.log --scene quad --method gears --script badlight.txt
expect_error $? "badlight.txt':1: light: the scene's lights are 0 to 0, not 1" badlight.log
printf 'time 5\n' >badtime.txt
view badtime.log --scene flag --method gears --script badtime.txt
expect_error $? "badtime.txt':1: time: the animation runs from 0 to 2 s, not 5" badtime.log
printf 'time 0.5\n' >stilltime.txt
view stilltime.log --scene quad --method gears --script stilltime.txt
expect_error $? "stilltime.txt':1: time: the scene has no animation" stilltime.log
env -u DISPLAY -u WAYLAND_DISPLAY "$bin" view --scene quad >nodisplay.log 2>&1
expect_error $? "no display" nodisplay.log

if [ "$failed" -ne 0 ]; then exit 1; fi
echo "PASS"
