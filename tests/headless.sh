#!/usr/bin/env bash
# Runs a command under its own headless X server (xvfb-run -a), one such command at a time, for
# tests/view_test.cpp. Usage: headless.sh COMMAND [ARGS...]; exits with the command's code.
#
# Two xvfb-run started together (ctest -j2) sometimes leave a client unable to open its
# display, hence the lock. And xvfb-run kills its Xvfb without waiting for it to exit: the next
# xvfb-run may then pick the display number that server is still giving up, and its client fails
# with "Failed to open display". So the lock is held until that Xvfb is gone.
set -u
xvfb_count() {
  local n=0 comm
  for comm in /proc/[0-9]*/comm; do
    [ "$(cat "$comm" 2>/dev/null)" = Xvfb ] && n=$((n + 1))
  done
  echo "$n"
}
exec 9>/tmp/rtt-view-tests.lock
flock 9
before=$(xvfb_count)
errors=$(mktemp)
xvfb-run -a -e "$errors" -s '-screen 0 640x480x24' "$@"
rc=$?
# When the command failed, what the X server said (a failed start, a display in use).
[ "$rc" -eq 0 ] || { echo "headless.sh: Xvfb's messages:"; cat "$errors"; } >&2
rm -f "$errors"
for _ in $(seq 100); do  # up to 5 s
  [ "$(xvfb_count)" -le "$before" ] && break
  sleep 0.05
done
exit "$rc"
