#!/usr/bin/env bash
# SIGINT and SIGTERM while `render` writes its outputs: the process dies of the signal (exit
# status 128 + signal), and the hidden temporary it was writing (.NAME.partial-PID, up to the size
# of the output) is removed on the way out. The final names are never half-written (the rename is
# atomic), so a temporary left behind would be the only trace.
#   signal_test.sh PENUMBRA_BINARY
set -uo pipefail
bin="$1"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
export PENUMBRA_NO_PROGRESS=1
# Job control: a background job of a non-interactive shell would otherwise start with SIGINT
# ignored (and the CLI keeps ignored signals ignored).
set -m
passed=0
failed=0
ok() { passed=$((passed + 1)); }
bad() {
  echo "FAIL: $*"
  failed=$((failed + 1))
}

# One run: start a render whose AOVs take a while to write, wait until a temporary exists, send
# the signal, check what is left.
interrupt_while_writing() {
  local signal="$1" number="$2" out="$work/$1"
  mkdir -p "$out"
  "$bin" render --scene quad --method shadow_map --samples 1 --size 3072x3072 \
    --aov position,normal,depth,uv --out "$out" >/dev/null 2>"$out.err" &
  local pid=$!
  local seen=""
  for _ in $(seq 1 3000); do  # up to 60 s (the frame itself takes a few seconds)
    if [ -n "$(find "$out" -maxdepth 1 -name '.*.partial-*' -print -quit 2>/dev/null)" ]; then
      seen=1
      break
    fi
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.02
  done
  if [ -z "$seen" ]; then
    kill -KILL "$pid" 2>/dev/null
    wait "$pid" 2>/dev/null
    bad "$signal: no temporary file was seen while the render wrote (nothing to interrupt)"
    return
  fi
  kill "-$signal" "$pid"
  wait "$pid"
  local rc=$?
  [ "$rc" -eq $((128 + number)) ] && ok || bad "$signal: exit status $rc (want $((128 + number)), killed by the signal)"
  local left
  left="$(find "$out" -name '*.partial-*')"
  [ -z "$left" ] && ok || bad "$signal: temporaries left behind: $left"
}

interrupt_while_writing INT 2
interrupt_while_writing TERM 15

echo "signal: $passed passed, $failed failed"
[ "$failed" -eq 0 ]
