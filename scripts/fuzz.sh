#!/usr/bin/env bash
# Builds the libFuzzer targets (Debian clang, -fsanitize=fuzzer,address,undefined) and runs each for
# a bounded time, then replays the mesh corpus under valgrind; any crash, hang, leak, sanitizer or
# valgrind report fails the run.
#   scripts/fuzz.sh [SECONDS_PER_TARGET (default 60)] [TARGET...]   (targets: scene mesh)
# Findings (crash-*, timeout-*, oom-* files) and the grown corpora stay under build/fuzz/.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
shift || true
targets=("$@")
[ "${#targets[@]}" -gt 0 ] || targets=(scene mesh)
scripts/setup.sh
out=build/fuzz
mkdir -p "$out"

# The project's sources the targets exercise (core, io, scene), compiled with clang and the
# sanitizers; the Debian libraries they use are linked as built.
sources=(src/penumbra/core/*.cpp src/penumbra/io/*.cpp src/penumbra/scene/*.cpp)
# The SIMD dispatch's target set, as CMakeLists.txt defines it for every module (core/simd.cpp).
hwy_defines=(-DHWY_COMPILE_ALL_ATTAINABLE -DHWY_DISABLED_TARGETS=HWY_SSSE3)
flags=(-std=c++20 -g -O1 -fno-omit-frame-pointer -fsanitize=fuzzer,address,undefined
       -fno-sanitize-recover=undefined -DGLM_FORCE_XYZW_ONLY -Isrc "${hwy_defines[@]}"
       $(pkg-config --cflags OpenEXR stb))
libs=($(pkg-config --libs OpenEXR assimp tbb stb zlib libhwy))

# Each source compiled once (rebuilt when it or any header is newer), shared by both targets; one
# compiler per core.
newest_header="$(find src -name '*.hpp' -printf '%T@ %p\n' | sort -n | tail -1 | cut -d' ' -f2)"
compile() {  # compile OBJ_DIR COMPILER FLAGS... -- SOURCES...: fills `objects`
  local dir="$1" compiler="$2" src obj pids=()
  shift 2
  local cflags=()
  while [ "$1" != "--" ]; do cflags+=("$1"); shift; done
  shift
  mkdir -p "$dir"
  objects=()
  for src in "$@"; do
    obj="$dir/$(echo "$src" | tr / _).o"
    if [ ! -f "$obj" ] || [ "$src" -nt "$obj" ] || [ "$newest_header" -nt "$obj" ]; then
      while [ "$(jobs -rp | wc -l)" -ge "$(nproc)" ]; do wait -n; done
      echo "compiling $src"
      # shellcheck disable=SC2086 # "ccache clang++" is two words
      $compiler "${cflags[@]}" -c "$src" -o "$obj" &
      pids+=($!)
    fi
    objects+=("$obj")
  done
  local pid
  for pid in "${pids[@]}"; do wait "$pid"; done
}
# Through ccache when it is installed (as scripts/build.sh does).
cxx=(clang++)
if command -v ccache >/dev/null; then
  cxx=(ccache clang++)
  export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1
fi
compile "$out/obj" "${cxx[*]}" \
  "${flags[@]/-fsanitize=fuzzer,address,undefined/-fsanitize=fuzzer-no-link,address,undefined}" \
  -- "${sources[@]}"
for t in "${targets[@]}"; do
  bin="$out/fuzz_$t"
  echo "linking $bin"
  clang++ "${flags[@]}" "fuzz/fuzz_$t.cpp" "${objects[@]}" "${libs[@]}" -o "$bin"
done

# Seed corpora from tests/data: scene files for the scene target; meshes (format byte first).
seed() {
  local t="$1" dir="$out/corpus_$1"
  mkdir -p "$dir"
  if [ "$t" = scene ]; then
    cp tests/data/scenes/*.json tests/data/scenes/broken/*.json "$dir/" 2>/dev/null || true
  else
    local i=0
    for f in tests/data/scenes/*.off tests/data/scenes/broken/*.off tests/data/meshes/broken/*.off; do
      [ -f "$f" ] && { printf '\x00'; cat "$f"; } >"$dir/off_$((i++))"
    done
    for f in tests/data/scenes/broken/*.ply tests/data/meshes/broken/*.ply; do
      [ -f "$f" ] && { printf '\x01'; cat "$f"; } >"$dir/ply_$((i++))"
    done
    for f in tests/data/scenes/*.obj tests/data/scenes/broken/*.obj; do
      [ -f "$f" ] && { printf '\x02'; cat "$f"; } >"$dir/obj_$((i++))"
    done
    for f in tests/data/meshes/gltf/*.gltf; do
      [ -f "$f" ] && { printf '\x04'; cat "$f"; } >"$dir/gltf_$((i++))"
    done
    for f in tests/data/meshes/gltf/*.glb; do
      [ -f "$f" ] && { printf '\x05'; cat "$f"; } >"$dir/glb_$((i++))"
    done
    printf '\x03solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n' >"$dir/stl_ascii"
  fi
}

suppressions="$(pwd)/fuzz/lsan.supp"
status=0
for t in "${targets[@]}"; do
  seed "$t"
  echo "fuzzing $t for ${seconds}s"
  # -timeout: an input taking over 10 s is a hang; -rss_limit_mb: a runaway allocation is a finding.
  if ! (cd "$out" && ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS="suppressions=$suppressions" \
    UBSAN_OPTIONS=print_stacktrace=1 \
    "./fuzz_$t" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
    -print_final_stats=1 -artifact_prefix="$t-" "corpus_$t" >"fuzz_$t.log" 2>&1); then
    echo "FINDING in $t: see $out/fuzz_$t.log and $out/$t-*"
    tail -40 "$out/fuzz_$t.log"
    status=1
  else
    grep -E "stat::number_of_executed_units|Done" "$out/fuzz_$t.log" | tail -2
  fi
done

# The mesh corpus replayed under valgrind in a plain build: assimp is not instrumented, so ASan
# misses its out-of-bounds writes, which corrupt the heap and crash much later (not on replay).
if [[ " ${targets[*]} " == *" mesh "* ]]; then
  compile "$out/obj_plain" g++ -std=c++20 -g -O1 -DGLM_FORCE_XYZW_ONLY -Isrc "${hwy_defines[@]}" \
    $(pkg-config --cflags OpenEXR stb) -- "${sources[@]}" fuzz/fuzz_mesh.cpp fuzz/replay_main.cpp
  g++ "${objects[@]}" "${libs[@]}" -o "$out/replay_mesh"
  echo "replaying $(ls "$out/corpus_mesh" | wc -l) mesh inputs under valgrind"
  if ! valgrind -q --error-exitcode=9 "$out/replay_mesh" "$out"/corpus_mesh/* \
    >"$out/valgrind_mesh.log" 2>&1; then
    echo "FINDING in the valgrind replay: see $out/valgrind_mesh.log"
    grep -v '^replaying' "$out/valgrind_mesh.log" | head -40
    awk '/^replaying/ {input = $2} /== Invalid/ {print "  input:", input; exit}' \
      "$out/valgrind_mesh.log"
    status=1
  fi
fi
exit "$status"
