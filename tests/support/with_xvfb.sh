#!/usr/bin/env bash
# Runs a command with its own Xvfb server, for the tests that render:
#   with_xvfb.sh [--screen WxHxD] [--] COMMAND [ARGS...]
# Exits with COMMAND's status, or 125 (without running it) if no server starts.
#
# Why not `xvfb-run -a`: its server resets whenever its last client disconnects
# and refuses connections meanwhile, so a process that closes a display and opens
# the next (Canopy's display probe then ParaView's window, one render window after
# another in a test) fails now and then with "bad X server connection"; and it
# guesses a free display number from /tmp/.X*-lock files, which races with other
# servers starting. Here the server picks a free display itself (-displayfd),
# never resets (-noreset), admits only clients with this run's cookie, and is
# always stopped. Several of these run in parallel safely.
set -euo pipefail

screen=1280x1024x24
while (($#)); do
  case "$1" in
    --screen) screen="$2"; shift 2 ;;
    --) shift; break ;;
    *) break ;;
  esac
done
if ((!$#)); then
  echo "usage: with_xvfb.sh [--screen WxHxD] [--] COMMAND [ARGS...]" >&2
  exit 2
fi
fail() {
  echo "with_xvfb: $*" >&2
  exit 125
}
# What the server said that matters (not its usage text).
server_log() {
  grep -E '\(EE\)|[Ff]atal|[Ee]rror|Invalid|[Uu]nrecognized|[Cc]annot' "$work/log" | head -n 20 ||
    head -n 10 "$work/log"
}
for tool in Xvfb xauth xdpyinfo; do
  command -v "$tool" >/dev/null || fail "$tool is not installed (scripts/setup.sh installs it)"
done

work="$(mktemp -d "${TMPDIR:-/tmp}/canopy-xvfb.XXXXXX")"
server=
child=
cleanup() {
  if [ -n "$child" ]; then
    kill -TERM "$child" 2>/dev/null || true
  fi
  if [ -n "$server" ]; then
    kill -TERM "$server" 2>/dev/null || true
    # Give it a moment to remove its sockets, then make sure it is gone.
    for _ in $(seq 50); do
      kill -0 "$server" 2>/dev/null || break
      sleep 0.1
    done
    kill -KILL "$server" 2>/dev/null || true
    wait "$server" 2>/dev/null || true
  fi
  rm -rf "$work"
}
trap cleanup EXIT
trap 'exit 143' TERM
trap 'exit 130' INT
trap 'exit 129' HUP

# The server reads its cookie at start whatever display it ends up on; clients
# find it under the display's number, added once the number is known.
cookie="$(od -An -N16 -tx1 /dev/urandom | tr -d ' \n')"
: >"$work/auth"
xauth -q -f "$work/auth" add :0 MIT-MAGIC-COOKIE-1 "$cookie"

# setpriv --pdeathsig: the server dies with this script even if it is killed
# with SIGKILL (a test timeout), instead of living on without its client.
launcher=()
if command -v setpriv >/dev/null; then
  launcher=(setpriv --pdeathsig KILL --)
fi
"${launcher[@]}" Xvfb -displayfd 3 -noreset -nolisten tcp -screen 0 "$screen" \
  -auth "$work/auth" 3>"$work/display" >"$work/log" 2>&1 &
server=$!

# Xvfb writes the display number and a newline once it accepts connections.
timeout="${CANOPY_XVFB_TIMEOUT:-60}"
deadline=$((SECONDS + timeout))
display=
while :; do
  if [ -s "$work/display" ] && [ -z "$(tail -c 1 "$work/display")" ]; then
    display="$(head -n 1 "$work/display")"
    break
  fi
  if ! kill -0 "$server" 2>/dev/null; then
    wait "$server" && status=0 || status=$?
    server=
    fail "Xvfb exited with status $status before accepting connections (screen $screen):
$(server_log)"
  fi
  if ((SECONDS >= deadline)); then
    fail "Xvfb did not accept connections within $timeout s (CANOPY_XVFB_TIMEOUT):
$(server_log)"
  fi
  sleep 0.05
done
[[ "$display" =~ ^[0-9]+$ ]] || fail "Xvfb reported display '$display'"

xauth -q -f "$work/auth" add ":$display" MIT-MAGIC-COOKIE-1 "$cookie"
export DISPLAY=":$display" XAUTHORITY="$work/auth"
# OpenMPI's hwloc probes every X display it finds for GPUs; another test's server
# (tests run in parallel) refuses it our cookie and hwloc prints "Authorization
# required" into the output the checks read. scripts/run_miniapp.sh does the same.
export HWLOC_COMPONENTS="${HWLOC_COMPONENTS:--gl}"
# The server said it is ready; a real client connection proves it.
xdpyinfo >/dev/null 2>"$work/xdpyinfo.log" ||
  fail "Xvfb on $DISPLAY refuses connections: $(cat "$work/xdpyinfo.log")"

# In the background so that TERM/INT reach the traps (which stop the command
# and the server) while it runs. Tests may check the server is gone afterwards.
export CANOPY_XVFB_PID="$server"
"$@" &
child=$!
status=0
wait "$child" || status=$?
child=
exit "$status"
