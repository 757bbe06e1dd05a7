#!/usr/bin/env bash
# Installs the build tree BUILD into a fresh prefix under WORK, builds this example against it
# (nothing of the source tree on its include path) and runs it; then imports the installed
# Python module when one was built. Usage: run_installed.sh BUILD EXAMPLE_DIR WORK [PYTHON]
# $EMBED_FLAGS: compile and link flags of the example (the sanitizers', when the library has them).
set -euo pipefail
build=$1 example=$2 work=$3 python=${4:-}
rm -rf "$work"
cmake --install "$build" --prefix "$work/prefix" >/dev/null
cmake -S "$example" -B "$work/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$work/prefix" -DCMAKE_CXX_FLAGS="${EMBED_FLAGS:-}" \
  -DCMAKE_EXE_LINKER_FLAGS="${EMBED_FLAGS:-}" >/dev/null
cmake --build "$work/build" >/dev/null
"$work/build/embed"
test -x "$work/prefix/bin/penumbra"
if [ -n "$python" ]; then
  PYTHONPATH="$work/prefix/lib/python3/dist-packages" "$python" -c \
    'import penumbra; print("python module", penumbra.__version__, "from", penumbra.__file__)'
fi
