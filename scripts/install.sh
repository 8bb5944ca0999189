#!/usr/bin/env bash
# Install vvea-design and everything it needs on a fresh Debian/Ubuntu machine:
# the system libraries for off-screen rendering (apt, when available), then the
# Python package (pip, editable). Pass "test" to include the test tools.
set -euo pipefail
cd "$(dirname "$0")/.."

APT_PACKAGES=(libgl1 libegl1 libegl-mesa0 libgl1-mesa-dri libx11-6 libxrender1)

if command -v apt-get >/dev/null 2>&1; then
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then
    if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else SUDO="__none__"; fi
  fi
  if [ "$SUDO" = "__none__" ]; then
    echo "install.sh: not root and no sudo: skipping apt packages (${APT_PACKAGES[*]}); renders may fail" >&2
  else
    missing=()
    for p in "${APT_PACKAGES[@]}"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
    if [ ${#missing[@]} -gt 0 ]; then
      $SUDO apt-get update -qq
      DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
    fi
  fi
fi

extra=""
if [ "${1:-}" = "test" ]; then extra="[test]"; fi
python3 -m pip install --quiet --disable-pip-version-check -e ".${extra}"
