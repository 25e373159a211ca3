#!/usr/bin/env bash
# Drives `rtt view` in a real window with synthetic input (run under tests/headless.sh by
# tests/view_test.cpp): prints the camera (C), orbits with a left drag, dollies with the wheel,
# flies with W held, prints it again, switches tracer (T) and quits with Escape.
# Usage: view_input.sh RTT OUTPUT_FILE [rtt view options]; exits with rtt's code.
set -u
rtt=$1 out=$2
shift 2
"$rtt" view --size 96x72 -q "$@" >"$out" 2>&1 &
pid=$!
window=""
for _ in $(seq 1200); do  # up to a minute: a sanitizer build under load starts slowly
  # The title becomes the stats line after the first frame: the window then takes input.
  window=$(xdotool search --name '^rtt view [|]' 2>/dev/null | head -1)
  [ -n "$window" ] && break
  kill -0 "$pid" 2>/dev/null || break  # the viewer has ended without a window
  sleep 0.05
done
if [ -z "$window" ]; then
  kill "$pid" 2>/dev/null
  wait "$pid"
  # On stderr too: tests/headless.sh runs the script again when the display could not be opened.
  echo "no window appeared" >>"$out"
  cat "$out" >&2
  exit 1
fi
xdotool windowfocus --sync "$window"
sleep 0.3
step() { "$@"; sleep 0.2; }
step xdotool key c
step xdotool mousemove --window "$window" 40 40
step xdotool mousedown 1
step xdotool mousemove --window "$window" 60 45
step xdotool mouseup 1
step xdotool click 4
step xdotool keydown w
step xdotool keyup w
step xdotool key t
step xdotool key c
xdotool key Escape
wait "$pid"
