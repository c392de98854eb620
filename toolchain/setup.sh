#!/usr/bin/env bash
# Installs every Debian package trueaxis needs and creates the user LinuxCNC's
# tests run as (and removes the link to a user-owned kinematics module an
# earlier setup made, below); says each thing it changes on one line, and
# changes and says nothing when all of it is there. Safe to run again. Needs
# root (or sudo) only when something is missing.
set -euo pipefail

packages=(
  cmake ninja-build g++ pkg-config
  libeigen3-dev catch2 libmodbus-dev
  gcc-arm-none-eabi binutils-arm-none-eabi libnewlib-arm-none-eabi libstdc++-arm-none-eabi-newlib
  qemu-system-arm
  mbpoll python3 python3-matplotlib
  clang libclang-rt-14-dev llvm  # toolchain/fuzz.sh: libFuzzer, ASan/UBSan runtimes, llvm-symbolizer
  # integrations/linuxcnc: LinuxCNC (rs274, linuxcnc, halcompile) and the remap's Modbus client
  linuxcnc-uspace linuxcnc-uspace-dev python3-pymodbus python3-serial python3-serial-asyncio
  chromium  # tests/sim/tools/test_report_pages.py: every report rendered headless
  pyflakes3  # tests/lint: the Python lint
)

# LinuxCNC refuses to run as root: its headless tests (tests/linuxcnc) run it as
# this user, which has no password and no rights beyond its own home.
ci_user=trueaxis-ci

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done

make_ci_user() {
  if ! id -u "$ci_user" >/dev/null 2>&1; then
    local as_root=()
    if [ "$(id -u)" -ne 0 ]; then
      if ! command -v sudo >/dev/null; then
        echo "setup: cannot create the user $ci_user (needs root): the LinuxCNC tests will fail" >&2
        return 0
      fi
      as_root=(sudo)
    fi
    if "${as_root[@]}" useradd --create-home --shell /usr/sbin/nologin "$ci_user"; then
      echo "setup: created the user $ci_user (no password, no login shell: LinuxCNC's tests run as it)"
    else
      echo "setup: creating the user $ci_user failed: the LinuxCNC tests will fail" >&2
    fi
  fi
}

# LinuxCNC's rtapi_app (setuid root) loads real-time modules only from its own
# folder. An earlier setup linked the project's kinematics module there to a
# file in a folder of the calling user's, through which that user could run
# code as root: the link is removed. The tests (tests/linuxcnc/test_scenarios.py)
# and a controller install the module as a root-owned file instead
# (integrations/linuxcnc/kins/install.sh, as root).
kins_link=/usr/lib/linuxcnc/modules/trueaxis_kins.so
old_kins_dir=/var/lib/trueaxis
unlink_kins_module() {
  [ -L "$kins_link" ] || return 0
  local as_root=()
  if [ "$(id -u)" -ne 0 ]; then
    if ! command -v sudo >/dev/null || ! sudo -n true 2>/dev/null; then
      echo "setup: $kins_link is a link to $(readlink "$kins_link"), through which its owner can run code as root: remove it as root (sudo rm $kins_link)" >&2
      return 0
    fi
    as_root=(sudo -n)
  fi
  if "${as_root[@]}" rm -f "$kins_link"; then
    echo "setup: removed the link $kins_link (its target's owner could run code as root through rtapi_app); the tests install the module as root (integrations/linuxcnc/kins/install.sh)"
  fi
  if [ -d "$old_kins_dir" ] && "${as_root[@]}" rm -rf "$old_kins_dir"; then
    echo "setup: removed $old_kins_dir, the old link's folder"
  fi
}

if [ "${#missing[@]}" -eq 0 ]; then
  make_ci_user
  unlink_kins_module
  exit 0
fi

echo "setup: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -q
"${sudo_cmd[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
echo "setup: installed ${missing[*]}"
make_ci_user
unlink_kins_module
