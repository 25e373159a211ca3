#!/usr/bin/env bash
# Runs a command under a headless X server of its own, for tests/view_test.cpp.
# Usage: headless.sh COMMAND [ARGS...]; exits with the command's code.
#
# Xvfb -displayfd picks a free display number itself and writes it only once it accepts
# clients: two of these never race for a number, and the command never starts before its
# server is up. (xvfb-run -a guessed a number from the lock files in /tmp, waited for a signal
# and set up an xauth cookie; under ctest -j2 on fresh machines a client sometimes got
# "Failed to open display :99".) -ac: no access control, so no cookie to get wrong. -noreset:
# by default Xvfb resets when its last client leaves, and a client connecting during that reset
# (the viewer, just after display_answers' probe left) is refused.
set -u
# One headless server at a time: the viewer tests run in parallel under ctest -j, and two Xvfb
# probing display numbers at once once handed a client a number it could not open (sanitizer
# build, "server already running" in the probing server's log). flock waits for the other.
exec 9>"${TMPDIR:-/tmp}/rtt-headless.lock"
flock 9
# Starts a server; sets `server`, `work` and `display`, or returns 1 with its messages printed.
start_server() {
  work=$(mktemp -d)
  Xvfb -displayfd 3 -screen 0 640x480x24 -nolisten tcp -ac -noreset 3>"$work/display" 2>"$work/errors" 9>&- &
  server=$!
  display=""
  for _ in $(seq 600); do  # up to 30 s: a sanitizer build under load starts slowly
    display=$(tr -dc 0-9 <"$work/display")
    [ -n "$display" ] && return 0
    kill -0 "$server" 2>/dev/null || break
    sleep 0.05
  done
  echo "headless.sh: Xvfb did not start:" >&2
  cat "$work/errors" >&2
  stop_server
  return 1
}
stop_server() {
  kill "$server" 2>/dev/null
  wait "$server" 2>/dev/null
  rm -rf "$work"
}
# Whether the server is up and a client can open its display (xdotool, where installed: a
# viewer under ctest -j2 was once refused the display :0 its live server had announced).
display_answers() {
  kill -0 "$server" 2>/dev/null || return 1
  command -v xdotool >/dev/null 2>&1 || return 0
  DISPLAY=":$display" xdotool getdisplaygeometry >/dev/null 2>&1
}
# Waits up to 10 s for display_answers.
wait_for_display() {
  for _ in $(seq 200); do
    display_answers && return 0
    sleep 0.05
  done
  return 1
}
# A failure while the display does not answer, or one that says the display could not be
# opened, is the server's, not the command's (CI runs had a viewer refused the display it was
# given): the command runs again on a new server, at most three times. Any other failure is the
# command's and is returned. The command's stderr is kept to tell the two apart.
for attempt in 1 2 3; do
  start_server || exit 1
  if ! wait_for_display && [ "$attempt" -lt 3 ]; then
    echo "headless.sh: no client could open :$display; a new server:" >&2
    cat "$work/errors" >&2
    stop_server
    continue
  fi
  DISPLAY=":$display" "$@" 9>&- 2>"$work/stderr"
  rc=$?
  cat "$work/stderr" >&2
  if [ "$rc" -ne 0 ] && [ "$attempt" -lt 3 ] &&
    { ! display_answers || grep -q 'Failed to open display' "$work/stderr"; }; then
    echo "headless.sh: the command could not use the X server on :$display; again:" >&2
    cat "$work/errors" >&2
    stop_server
    continue
  fi
  break
done
[ "$rc" -eq 0 ] || { echo "headless.sh: Xvfb's messages:"; cat "$work/errors"; } >&2
stop_server
exit "$rc"
