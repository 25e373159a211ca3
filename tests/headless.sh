#!/usr/bin/env bash
# Runs a command under a headless X server of its own, for tests/view_test.cpp.
# Usage: headless.sh COMMAND [ARGS...]; exits with the command's code.
#
# Xvfb -displayfd picks a free display number itself and writes it only once it accepts
# clients: two of these never race for a number, and the command never starts before its
# server is up. (xvfb-run -a guessed a number from the lock files in /tmp, waited for a signal
# and set up an xauth cookie; under ctest -j2 on fresh machines a client sometimes got
# "Failed to open display :99".) -ac: no access control, so no cookie to get wrong.
set -u
# One headless server at a time: the viewer tests run in parallel under ctest -j, and two Xvfb
# probing display numbers at once once handed a client a number it could not open (sanitizer
# build, "server already running" in the probing server's log). flock waits for the other.
exec 9>"${TMPDIR:-/tmp}/rtt-headless.lock"
flock 9
work=$(mktemp -d)
Xvfb -displayfd 3 -screen 0 640x480x24 -nolisten tcp -ac 3>"$work/display" 2>"$work/errors" 9>&- &
server=$!
stop_server() {
  kill "$server" 2>/dev/null
  wait "$server" 2>/dev/null
  rm -rf "$work"
}
display=""
for _ in $(seq 600); do  # up to 30 s: a sanitizer build under load starts slowly
  display=$(tr -dc 0-9 <"$work/display")
  [ -n "$display" ] && break
  kill -0 "$server" 2>/dev/null || break
  sleep 0.05
done
if [ -z "$display" ]; then
  echo "headless.sh: Xvfb did not start:" >&2
  cat "$work/errors" >&2
  stop_server
  exit 1
fi
DISPLAY=":$display" "$@" 9>&-
rc=$?
[ "$rc" -eq 0 ] || { echo "headless.sh: Xvfb's messages:"; cat "$work/errors"; } >&2
stop_server
exit "$rc"
