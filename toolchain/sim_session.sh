# Sourced by the demo scripts: a trueaxis-sim for the length of the script.
#   start_sim BIN_DIR [trueaxis-sim options...]
# makes a work directory ($work), starts trueaxis-sim on 127.0.0.1 port 0 with
# an NV file in it, waits for its "listening on" line and sets $port and
# $sim_line; stops the sim and removes $work when the script exits. Exits 3
# when the sim does not start within 10 s.
work="$(mktemp -d "${TMPDIR:-/tmp}/trueaxis-demo.XXXXXX")"
sim_pid=""
cleanup_sim() {
  if [ -n "$sim_pid" ]; then
    kill -TERM "$sim_pid" 2>/dev/null || true
    wait "$sim_pid" 2>/dev/null || true
  fi
  rm -rf "$work"
}
trap cleanup_sim EXIT

start_sim() {
  local bin_dir="$1"
  shift
  mkfifo "$work/out"
  "$bin_dir/trueaxis-sim" --port 0 --nv "$work/demo.nv" "$@" >"$work/out" &
  sim_pid=$!
  exec 3<"$work/out"
  port=""
  sim_line=""
  if IFS= read -r -t 10 sim_line <&3; then
    case "$sim_line" in
      "listening on "*) port="${sim_line##*:}" ;;
    esac
  fi
  if [ -z "$port" ]; then
    echo "demo: trueaxis-sim did not start" >&2
    exit 3
  fi
}

# The start of a calibration demo (demo_gantry.sh, demo_spindle.sh):
#   demo_start "$@"
# reads --bin-dir DIR, --keep DIR and --seed N (default 1) into $bin_dir, $keep
# and $seed; without --bin-dir installs what is missing and builds every
# trueaxis-* program into build/host/bin (target trueaxis-programs); starts the
# sim and makes $out_dir ($keep, or the work directory). Needs $root.
demo_start() {
  bin_dir=""
  keep=""
  seed=1
  while [ $# -gt 0 ]; do
    case "$1" in
      --bin-dir) bin_dir="$2"; shift 2 ;;
      --keep) keep="$2"; shift 2 ;;
      --seed) seed="$2"; shift 2 ;;
      *) echo "usage: $0 [--bin-dir DIR] [--keep DIR] [--seed N]" >&2; exit 2 ;;
    esac
  done
  if [ -z "$bin_dir" ]; then
    bash "$root/toolchain/setup.sh"
    cmake -S "$root" -B "$root/build/host" -G Ninja >/dev/null
    cmake --build "$root/build/host" --target trueaxis-programs
    bin_dir="$root/build/host/bin"
  fi
  start_sim "$bin_dir"
  out_dir="${keep:-$work}"
  mkdir -p "$out_dir"
  echo "demo: trueaxis-sim (pid $sim_pid) $sim_line"
}
