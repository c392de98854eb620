#!/usr/bin/env bash
# Installs every Debian package trueaxis needs, creates the user LinuxCNC's tests
# run as and links the kinematics module's place in LinuxCNC's module folder
# (below); says each thing it changes on one line, and changes and says nothing
# when all of it is there. Safe to run again. Needs root (or sudo) only when
# something is missing.
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

# LinuxCNC's rtapi_app loads real-time modules only from its own folder: the
# project's kinematics module (integrations/linuxcnc/kins, trueaxis_kins.so) is
# linked there to a file in a folder that belongs to the user who ran this
# script, so that the LinuxCNC tests can put the module they built in place
# without root (tests/linuxcnc/test_scenarios.py). A controller installs its
# module with root instead (integrations/linuxcnc/kins/README.md); a module
# installed there as a file is left alone. The user who owns the folder can run
# code as root through rtapi_app (setuid root): a development machine's setup.
kins_link=/usr/lib/linuxcnc/modules/trueaxis_kins.so
kins_dir=/var/lib/trueaxis
link_kins_module() {
  [ -d "$(dirname "$kins_link")" ] || return 0
  [ -L "$kins_link" ] && [ -d "$kins_dir" ] && return 0
  if [ -e "$kins_link" ] && [ ! -L "$kins_link" ]; then
    echo "setup: $kins_link is an installed module: left alone (the LinuxCNC kinematics tests need the link)" >&2
    return 0
  fi
  local owner="${SUDO_USER:-$(id -un)}"
  local as_root=()
  if [ "$(id -u)" -ne 0 ]; then
    if ! command -v sudo >/dev/null || ! sudo -n true 2>/dev/null; then
      echo "setup: cannot link $kins_link (needs root: sudo bash toolchain/setup.sh): the LinuxCNC kinematics tests will fail" >&2
      return 0
    fi
    as_root=(sudo -n)
  fi
  if "${as_root[@]}" mkdir -p "$kins_dir" && "${as_root[@]}" chown "$owner" "$kins_dir" &&
    "${as_root[@]}" ln -sfn "$kins_dir/trueaxis_kins.so" "$kins_link"; then
    echo "setup: linked $kins_link to $kins_dir/trueaxis_kins.so ($kins_dir belongs to $owner: the LinuxCNC tests put their module there)"
  else
    echo "setup: linking $kins_link failed: the LinuxCNC kinematics tests will fail" >&2
  fi
}

if [ "${#missing[@]}" -eq 0 ]; then
  make_ci_user
  link_kins_module
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
link_kins_module
