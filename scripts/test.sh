#!/usr/bin/env bash
# The project's test command: installs what the tests need on a fresh Debian/Ubuntu machine
# (Mesa's software Vulkan driver when no Vulkan driver is present), then runs every test.
set -euo pipefail
cd "$(dirname "$0")/.."

as_root() { if [ "$(id -u)" = 0 ]; then "$@"; else sudo "$@"; fi; }

apt_updated=0
apt_install() {
  if [ "$apt_updated" = 0 ]; then
    as_root apt-get update -qq
    apt_updated=1
  fi
  as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$@"
}

# A Vulkan driver: any installed ICD manifest will do; otherwise Mesa's lavapipe (llvmpipe).
# (`ls a b` fails when either directory is missing, so each is checked on its own.)
if ! ls /usr/share/vulkan/icd.d/*.json >/dev/null 2>&1 && ! ls /etc/vulkan/icd.d/*.json >/dev/null 2>&1; then
  echo "test.sh: no Vulkan driver found, installing mesa-vulkan-drivers (software Vulkan)"
  apt_install mesa-vulkan-drivers libvulkan1
fi

# The sandbox screenshot test renders a real window under Xvfb.
if ! command -v xvfb-run >/dev/null 2>&1; then
  echo "test.sh: installing xvfb (virtual X server for the sandbox screenshot test)"
  apt_install xvfb xauth
fi

# Mesa's drivers warn on every device creation without a runtime directory.
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
  export XDG_RUNTIME_DIR="/tmp/xdg-runtime-$(id -u)"
  mkdir -p "$XDG_RUNTIME_DIR" && chmod 700 "$XDG_RUNTIME_DIR"
fi

cargo test --workspace --release "$@"
