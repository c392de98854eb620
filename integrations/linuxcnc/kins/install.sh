#!/usr/bin/env bash
# Installs the kinematics module into LinuxCNC's module folder, as root:
#   sudo bash integrations/linuxcnc/kins/install.sh [build/host/linuxcnc/trueaxis_kins.so]
# LinuxCNC's rtapi_app is setuid root and loads every real-time module from
# /usr/lib/linuxcnc/modules, so the module there must be a root-owned file that
# no one else may write (never a link to a user's file: its owner could then run
# code as root). The file is copied in, root:root, mode 0644, in one rename (a
# LinuxCNC starting meanwhile loads the old module or the new, never half of
# one). Says what it did on one line; exit 1 with one line on any failure.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
built=${1:-$here/../../../build/host/linuxcnc/trueaxis_kins.so}
folder=/usr/lib/linuxcnc/modules
target=$folder/trueaxis_kins.so

fail() { echo "install.sh: $*" >&2; exit 1; }
[ "$(id -u)" -eq 0 ] || fail "run it as root (sudo bash $0): LinuxCNC's module folder is root's"
[ -f "$built" ] || fail "$built: no such module (cmake --build build/host --target trueaxis_kins; linuxcnc-uspace-dev installed?)"
[ -d "$folder" ] || fail "$folder: no such folder (linuxcnc-uspace installed?)"
was=""
if [ -L "$target" ]; then
  was=" in place of the link to $(readlink "$target")"
fi
install -o root -g root -m 0644 "$built" "$target.new"
mv -f "$target.new" "$target"
echo "install.sh: installed $target (root:root 0644) from $built$was"
